// A mushroom: a 4 mm stem 15 mm tall, a cone out to 14 mm over 5 mm, and a flattened cap
// (a sphere of r 14 squashed to half its height) on top: a prism, a steep overhang, and a cap
// whose underside is nearly flat. Not one of the benchmarks' defaults, never tuned to: pass it
// as EXTRA to tests/bench/compare_supports.sh or adaptive_layers.sh.
$fn = 96;
union() { cylinder(r = 4, h = 15); translate([0, 0, 15]) cylinder(r1 = 4, r2 = 14, h = 5);
          translate([0, 0, 20]) scale([1, 1, 0.5]) sphere(r = 14); }
