// A ball (r 10) on a 2 mm stick 20 mm tall, 38 mm in all: a prism half its height, then a
// sphere whose underside meets the stick nearly flat. A held-out model, never tuned to: pass
// it as EXTRA to tests/bench/adaptive_layers.sh or tests/bench/compare_supports.sh.
union() { cylinder(r = 2, h = 20, $fn = 32); translate([0, 0, 28]) sphere(r = 10, $fn = 64); }
