// A six-pointed star twisted by 90 degrees over 28 mm and tapering to 70%, with a flat top:
// its walls lean a little everywhere, more at the points, and its top is a flat level that a
// plan must land. Written for the comparison of layer plans before any plan was judged
// on it, and never tuned to (tests/bench/plan_vs_peers.sh).
points = 6;
star = [for (k = [0 : 2 * points - 1]) let(a = 180 * k / points, r = k % 2 ? 7 : 15) [r * cos(a), r * sin(a)]];
linear_extrude(height = 28, twist = 90, scale = 0.7, slices = 56) polygon(star);
