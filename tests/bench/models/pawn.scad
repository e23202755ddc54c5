// A chess pawn, 36 mm tall: a stepped base (flat tops at 3 and 5 mm), a concave waist, a
// collar (a flat ring at 24 mm on a lip whose underside faces down), and a ball for a head whose
// top is nearly flat. Written for the comparison of layer plans before any plan was
// judged on it, and never tuned to (tests/bench/plan_vs_peers.sh).
$fn = 96;
rotate_extrude() polygon([
  [0, 0], [13, 0], [13, 3], [11.5, 3], [11.5, 5], [10, 5],
  // the waist: a concave curve from r 10 at 5 mm to r 4.5 at 21 mm
  for (k = [1 : 16]) let(z = 5 + k, u = k / 16) [10 - 5.5 * sin(90 * u), z],
  [7.5, 22], [7.5, 24], [5, 24], [4.2, 26], [0, 26]]);
translate([0, 0, 30]) sphere(r = 6);
