// A bottle, 45 mm: a body of r 11 with a rounded shoulder, a neck of r 4, a lip (overhang
// under a ring of r 5.5, flat on top) and a flat top at 45 mm; a shallow punt (a dome pushed
// in from below, 2 mm deep) under the body. Written for the comparison of layer plans
// before any plan was judged on it, and never tuned to (tests/bench/plan_vs_peers.sh).
$fn = 96;
rotate_extrude() polygon([
  [0, 2], [6, 0.5], [8, 0], [11, 0], [11, 26],
  for (k = [1 : 12]) let(a = 90 * k / 12) [4 + 7 * cos(a), 26 + 9 * sin(a)],
  [4, 40], [5.5, 41.5], [5.5, 43], [4.8, 45], [0, 45]]);
