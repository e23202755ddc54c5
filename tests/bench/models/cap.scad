// A spherical cap: the top 14 mm of a sphere of radius 20 on a 3 mm disc of the cap's own
// radius; it flattens all the way to its top, where a layer's distance error grows without
// bound as the surface turns horizontal. Written for the comparison of layer plans
// before any plan was judged on it, and never tuned to (tests/bench/plan_vs_peers.sh).
$fn = 160;
r = 20; h = 14; base = sqrt(r * r - (r - h) * (r - h));
union() {
  cylinder(r = base, h = 3);
  translate([0, 0, 3 - (r - h)]) intersection() {
    sphere(r = r);
    translate([0, 0, r - h + r]) cube(2 * r, center = true);
  }
}
