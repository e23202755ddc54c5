// A 10 x 10 x 30 mm column with a flat shelf (20 mm out, 3 mm thick, at 12 mm) and a ledge
// leaning up at 30 degrees from 25 mm. A held-out model, never tuned to: pass it as EXTRA to
// tests/bench/compare_supports.sh.
union() { cube([10, 10, 30]); translate([0, 0, 12]) cube([30, 10, 3]);
          translate([0, 0, 25]) rotate([0, -30, 0]) cube([25, 10, 2]); }
