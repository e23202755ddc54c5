// Benchmark model for adaptive layers (tests/bench/adaptive_layers.sh): three stepped tiers
// whose flat tops are off any layer grid (4.1, 8.0 and 13.3 mm), with flanks at 20, 45 and 70
// degrees from the horizontal, under a 45-degree cone ending at 20 mm.
$fn = 96;
// A tier from z0 to z1: a square of half-width w at the bottom, leaning in by (z1 - z0) /
// tan(angle) at the top.
module tier(z0, z1, w, angle) {
  inset = (z1 - z0) / tan(angle);
  translate([0, 0, z0]) hull() {
    translate([-w, -w, 0]) cube([2 * w, 2 * w, 0.001]);
    translate([-(w - inset), -(w - inset), z1 - z0 - 0.001]) cube([2 * (w - inset), 2 * (w - inset), 0.001]);
  }
}
union() {
  tier(0, 4.1, 20, 70);
  tier(4.1, 8.0, 15, 45);
  tier(8.0, 13.3, 9, 70);
  translate([0, 0, 13.3]) cylinder(h = 6.7, r1 = 6.7, r2 = 0);
  // A shallow ramp on the first tier: 20 degrees.
  translate([0, 0, 4.1]) hull() {
    translate([-19, 10, 0]) cube([38, 8, 0.001]);
    translate([-19, 16, 2.1838]) cube([38, 0.5, 0.001]);  // rises 6 mm in y at 20 degrees
  }
}
