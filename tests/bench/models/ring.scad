// A ring standing on its edge (a torus, R 12, r 4): overhangs under its outside and its
// hole's ceiling, 32 mm tall. A held-out model, never tuned to: pass it as EXTRA to
// tests/bench/adaptive_layers.sh or tests/bench/compare_supports.sh.
rotate([90, 0, 0]) rotate_extrude($fn = 96) translate([12, 0]) circle(r = 4, $fn = 48);
