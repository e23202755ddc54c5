// A spur gear: 24 involute-like teeth (module 1.5, 8 mm face) with both faces' tooth edges
// chamfered at 45 degrees 0.6 mm, a hub 12 mm across rising to 14 mm with a rounded top edge,
// and a 5 mm bore. Mostly vertical walls between flat levels, short slopes at the chamfers.
// Written for the comparison of layer plans before any plan was judged on it, and never
// tuned to (tests/bench/plan_vs_peers.sh).
teeth = 24; m = 1.5;
pitch_r = teeth * m / 2; root_r = pitch_r - 1.25 * m; tip_r = pitch_r + m;
function tooth_profile() = [
  for (k = [0 : teeth - 1]) let(a = 360 * k / teeth) each [
    [root_r * cos(a - 5.5), root_r * sin(a - 5.5)],
    [pitch_r * cos(a - 3.6), pitch_r * sin(a - 3.6)],
    [tip_r * cos(a - 1.8), tip_r * sin(a - 1.8)],
    [tip_r * cos(a + 1.8), tip_r * sin(a + 1.8)],
    [pitch_r * cos(a + 3.6), pitch_r * sin(a + 3.6)],
    [root_r * cos(a + 5.5), root_r * sin(a + 5.5)]]];
difference() {
  union() {
    intersection() {
      linear_extrude(height = 8) polygon(tooth_profile());
      // the chamfers: cones opening 45 degrees away from each face
      cylinder(r1 = tip_r - 0.6, r2 = tip_r + 7.4, h = 8, $fn = 96);
      translate([0, 0, 8]) mirror([0, 0, 1]) cylinder(r1 = tip_r - 0.6, r2 = tip_r + 7.4, h = 8, $fn = 96);
    }
    cylinder(r = 6, h = 12.5, $fn = 64);
    translate([0, 0, 12.5]) rotate_extrude($fn = 64) translate([4.5, 0]) circle(r = 1.5, $fn = 32);
    cylinder(r = 4.5, h = 14, $fn = 64);
  }
  translate([0, 0, -1]) cylinder(r = 2.5, h = 20, $fn = 32);
}
