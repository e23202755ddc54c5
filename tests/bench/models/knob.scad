// A cabinet knob, 23.37 mm: a round foot chamfered 30 degrees from horizontal at its lower edge
// (a slope shallow enough that the thinnest layer steps far), a flat shoulder at 4.13 mm (off
// the 0.05 mm grid), an octagonal grip twisted 40 degrees and narrowing to 60%, a flat ledge at
// 15.62 mm and an ellipsoidal dome (radius 9, 7.75 tall) to the top. Written for the comparison
// of layer plans after the six others and before any plan was judged on it, to check that the
// plan was not tuned to them; never tuned to (tests/bench/plan_vs_peers.sh).
$fn = 120;
union() {
  // The foot: 30 degrees from horizontal for its first 1.2 mm, then vertical to the shoulder.
  rotate_extrude() polygon([[0, 0], [10 - 1.2 / tan(30), 0], [10, 1.2], [10, 4.13], [0, 4.13]]);
  // The grip, from the shoulder to the ledge.
  translate([0, 0, 4.13]) linear_extrude(height = 15.62 - 4.13, twist = 40, scale = 0.6, slices = 46)
    circle(r = 8, $fn = 8);
  // The dome on the ledge.
  translate([0, 0, 15.62]) scale([1, 1, 7.75 / 9]) intersection() {
    sphere(r = 9);
    translate([0, 0, 9]) cube(18, center = true);
  }
}
