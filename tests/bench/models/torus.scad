// A torus lying flat (R 15, r 6) on a 2 mm disc: slopes of every angle, flat at its top. Not
// one of the benchmarks' defaults: pass it as EXTRA to tests/bench/adaptive_layers.sh.
$fn = 96;
union() { cylinder(r = 12, h = 2); translate([0, 0, 6]) rotate_extrude() translate([15, 0]) circle(r = 6); }
