// A table: four 4 mm legs 25 mm tall under a 40 x 30 x 3 mm top, whose underside must be
// supported or bridged 32 mm between the legs. Not one of the benchmarks' defaults: pass it as
// EXTRA to tests/bench/compare_supports.sh.
union() { for (x = [-18, 14], y = [-13, 9]) translate([x, y, 0]) cube([4, 4, 25]);
          translate([-20, -15, 25]) cube([40, 30, 3]); }
