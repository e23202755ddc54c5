// A hollow box, 40 x 30 x 20 mm with 2 mm walls, closed all round: its lid's underside spans
// the 36 x 26 mm cavity inside. A held-out model, never tuned to: pass it as EXTRA to
// tests/bench/compare_supports.sh (try --rotate x:35 too).
difference() { cube([40, 30, 20]); translate([2, 2, 2]) cube([36, 26, 16]); }
