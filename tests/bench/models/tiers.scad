// A block with several flat levels off a 0.05 mm grid's simple multiples and close together:
// a 40 x 30 mm base 6.5 mm tall, a tier to 11.2 mm, a chamfered tier to 17 mm, a bore through
// it all and a cross-slot 3 mm deep in the top, then a 45-degree pyramid roof on one half up to
// 24.35 mm. Like OpenSCAD's example002, for flat levels; written for the comparison of
// layer plans before any plan was judged on it, and never tuned to (tests/bench/plan_vs_peers.sh).
difference() {
  union() {
    translate([-20, -15, 0]) cube([40, 30, 6.5]);
    translate([-15, -11, 6.5]) cube([30, 22, 4.7]);
    translate([0, 0, 11.2]) hull() {
      translate([-12, -9, 0]) cube([24, 18, 0.01]);
      translate([-10, -7, 5.79]) cube([20, 14, 0.01]);
    }
    // a pyramid roof on the left half, from 17 mm
    translate([-10, 0, 17]) hull() {
      translate([0, -7, 0]) cube([10, 14, 0.01]);
      translate([5, 0, 7.34]) cube([0.01, 0.01, 0.01], center = true);
    }
  }
  translate([0, 0, -1]) cylinder(r = 4, h = 40, $fn = 64);
  translate([3, -2, 14]) cube([12, 4, 10]);
  translate([-2, -15, 3.5]) cube([4, 30, 10]);
}
