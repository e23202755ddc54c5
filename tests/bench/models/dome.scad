// Benchmark model for adaptive layers (tests/bench/adaptive_layers.sh): a hemisphere of
// radius 15 mm on a 36 x 36 x 5 mm plinth. The plinth's top is a flat ring at 5 mm; the dome
// is vertical at its foot and flattens towards its top at 20 mm, where thin layers matter.
$fn = 128;
union() {
  translate([-18, -18, 0]) cube([36, 36, 5]);
  translate([0, 0, 5]) intersection() {
    sphere(r = 15);
    translate([-16, -16, 0]) cube([32, 32, 16]);
  }
}
