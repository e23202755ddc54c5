#!/usr/bin/env bash
# --orient auto on the bunny (50 mm tall as placed by --up y), a T (a 10 x 10 x
# 20 mm stem under a 50 x 10 x 5 mm bar), an arch (40 x 10 x 25 mm, a 24 mm opening) and the
# stl-models gearwheel: the resting face picked, the support volume estimate of the chosen
# orientation against the input's (orientation.h), the time --orient auto took (its own
# figure, median of REPEAT, default 3), and, to see whether the estimate ranks as the
# support stage does, the support filament the slicer lays in both orientations (UP Plus 2,
# ABS, supports everywhere, no raft, 0.2 mm layers).
#
# Usage: tests/bench/compare_orientations.sh [BUILD_DIR]   (default: build)
set -euo pipefail
cd "$(dirname "$0")/../.."
build=${1:-build}
repeat=${REPEAT:-3}
mahost=$build/mahost
[[ -x $mahost ]] || { echo "compare_orientations: $mahost not found; build first (scripts/build)" >&2; exit 2; }
command -v openscad >/dev/null || { echo "compare_orientations: openscad not found; run scripts/setup" >&2; exit 2; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

cat >"$work/tee.scad" <<'EOF'
union() { translate([-5, -5, 0]) cube([10, 10, 20]); translate([-25, -5, 20]) cube([50, 10, 5]); }
EOF
cat >"$work/arch.scad" <<'EOF'
difference() { translate([-20, -5, 0]) cube([40, 10, 25]);
               rotate([90, 0, 0]) cylinder(r = 12, h = 12, center = true, $fn = 96); }
EOF
for m in tee arch; do openscad -o "$work/$m.stl" "$work/$m.scad" >/dev/null 2>&1; done

support_m() {  # G-code -> support filament in m, from the ;TYPE: comments (absolute E)
  awk '/^;TYPE:/ { s = ($0 ~ /SUPPORT/) } /^G92/ { for (i = 2; i <= NF; i++) if ($i ~ /^E/) e = substr($i, 2) + 0 }
       /^G1 / { for (i = 2; i <= NF; i++) if ($i ~ /^E/) { v = substr($i, 2) + 0; if (s && v > e && $0 ~ / X| Y/) t += v - e; e = v } }
       END { printf "%.2f", t / 1000 }' "$1"
}

printf '%-10s %-60s %12s %12s %8s %10s %10s\n' model "orientation picked" "est. chosen" "est. input" "time" "sup. chosen" "sup. input"
for m in bunny tee arch gearwheel; do
  case $m in
    bunny) args=(data/bunny.stl --up y --units m --height 50) ;;
    gearwheel) args=(data/stl-models/objects/gearwheel.bin.stl) ;;
    *) args=("$work/$m.stl") ;;
  esac
  : >"$work/times"
  for ((run = 0; run < repeat; run++)); do
    line=$("$mahost" info "${args[@]}" --orient auto 2>/dev/null | sed -n 's/^orientation   //p')
    sed 's/.*, \([0-9.]*\) s$/\1/' <<<"$line" >>"$work/times"
  done
  took=$(sort -n "$work/times" | sed -n "$(((repeat + 1) / 2))p")
  picked=$(sed 's/^--orient auto: resting on the face whose outward normal was \(([^)]*)\), \([^;]*\);.*/\1, \2/' <<<"$line")
  chosen=$(sed 's/.*support material ~\([0-9]*\) mm^3 against.*/\1/' <<<"$line")
  input=$(sed 's/.*against \([0-9]*\) mm^3 as given.*/\1/' <<<"$line")
  for o in none auto; do
    "$mahost" slice "${args[@]}" --orient "$o" --support everywhere --no-raft --layer 0.2 \
      -o "$work/$m-$o.gcode" >/dev/null 2>&1
  done
  printf '%-10s %-60s %9s mm3 %9s mm3 %6s s %8s m %8s m\n' "$m" "${picked:0:60}" "$chosen" "$input" "$took" \
    "$(support_m "$work/$m-auto.gcode")" "$(support_m "$work/$m-none.gcode")"
done
