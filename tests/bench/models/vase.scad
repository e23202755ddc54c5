// Benchmark model for adaptive layers (tests/bench/adaptive_layers.sh): a twisted, tapering
// six-lobed vase 30 mm tall, closed (solid), with a rounded top: slopes that change with
// height everywhere, unlike the other two.
$fn = 96;
module lobes(r) {
  union() { for (a = [0 : 60 : 359]) rotate(a) translate([r * 0.55, 0]) circle(r = r * 0.5); circle(r = r * 0.7); }
}
union() {
  linear_extrude(height = 24, twist = 60, scale = 0.6, slices = 48) lobes(14);
  translate([0, 0, 24]) rotate(-60) scale([1, 1, 0.75]) intersection() {
    // the lobes' outline at the top, domed
    linear_extrude(height = 8, scale = 0.2, slices = 16) lobes(14 * 0.6);
  }
}
