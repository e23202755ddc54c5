#!/usr/bin/env bash
# mahost beside CuraEngine 4.13 and PrusaSlicer 2.5 on the paper's part: the Stanford bunny
# placed 50 mm tall (--up y --units m --height 50), at 0.15 mm and 0.2 mm layers, with the
# same machine and settings everywhere: the UP Plus 2 profile (140 x 140 x 135 mm, 0.4 mm
# nozzle, 0.45 mm lines, 0.5 mm / 0.3 mm first layer, 1.75 mm ABS), 2 perimeters, 20% grid
# infill, 3 top and 3 bottom layers, one skirt loop 3 mm out, no support and no raft (the
# profile has both; tests/bench/compare_supports.sh compares supports), the
# profile's speeds and accelerations. Prints one table: layers, each slicer's own print-time estimate, filament,
# wall time, CPU time and peak memory of the slicing run.
#
# Usage: tests/bench/compare_slicers.sh [BUILD_DIR]   (default: build; mahost must be built)
#        REPEAT=N tests/bench/compare_slicers.sh   runs each slicer N times (default 3) and
#        reports the run with the median wall time.
#
# All three slice the same placed, repaired mesh (mahost info --export), so the geometry is
# identical. CuraEngine needs Cura's JSON machine definitions (tests/bench/cura_definitions.sh
# fetches them once, and its cura_command passes every derived setting explicitly: CuraEngine
# does not evaluate the definitions' formulas, the Cura front end does). CuraEngine alone
# leaves its header's ;TIME:6666 and filament placeholders for the front end to fill: its time
# is the last ;TIME_ELAPSED, its filament read back from E.
set -euo pipefail
cd "$(dirname "$0")/../.."
build=${1:-build}
repeat=${REPEAT:-3}
[[ $repeat =~ ^[1-9][0-9]*$ ]] || { echo "compare_slicers: REPEAT must be a whole number >= 1" >&2; exit 2; }
mahost=$build/mahost
[[ -x $mahost ]] || { echo "compare_slicers: $mahost not found; build first (scripts/build)" >&2; exit 2; }
for tool in CuraEngine prusa-slicer /usr/bin/time; do
  command -v "$tool" >/dev/null || { echo "compare_slicers: $tool not found; run scripts/setup" >&2; exit 2; }
done

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# --- Cura's machine definitions ------------------------------------------------------------
source tests/bench/cura_definitions.sh  # (the script runs from the repo root)

# --- the part --------------------------------------------------------------------------------
model=$work/bunny50.stl
"$mahost" info data/bunny.stl --up y --units m --height 50 --export "$model" >/dev/null 2>&1

source tests/bench/timed.sh

# Net filament (mm) of a program: E travelled forward, across G92 resets, either E mode.
filament_of() {
  awk '
    /^M82/ { rel = 0 } /^M83/ { rel = 1 }
    /^G9[01]/ { rel = ($1 == "G91") }
    /^G92/ { for (i = 2; i <= NF; i++) if ($i ~ /^E/) { total += e - start; e = substr($i, 2) + 0; start = e } }
    /^G[01] / { for (i = 2; i <= NF; i++) if ($i ~ /^E/) { v = substr($i, 2) + 0; e = rel ? e + v : v } }
    END { total += e - start; printf "%.0f", total }' "$1"
}

hms() { awk -v s="$1" 'BEGIN { printf "%dh %02dm %02ds", s / 3600, (s % 3600) / 60, s % 60 }'; }

rows=()
declare -A walls  # "slicer layer" -> wall seconds
row() {  # slicer layer layers seconds filament_mm (then the run's figures from $work/time)
  local wall user sys peak
  read -r wall user sys peak <"$work/time"
  walls["$1 $2"]=$wall
  rows+=("$(printf '%-22s %5s %7s %13s %9.2f m %8.2f s %8.2f s %7.1f MiB' "$1" "$2" "$3" "$(hms "$4")" \
    "$(awk -v f="$5" 'BEGIN { print f / 1000 }')" "$wall" "$(awk -v u="$user" -v s="$sys" 'BEGIN { print u + s }')" \
    "$(awk -v k="$peak" 'BEGIN { print k / 1024 }')")")
}

for layer in 0.15 0.2; do
  # mahost: best (the default), the paper's MA contour and the mid-layer section other slicers use.
  for contour in best ma mid; do
    out=$work/mahost-$contour-$layer.gcode
    timed "$mahost" slice data/bunny.stl --up y --units m --height 50 --layer "$layer" --support none --no-raft \
      --contour "$contour" -o "$out"
    row "mahost ($contour)" "$layer" "$(grep -m1 '^;LAYER_COUNT:' "$out" | cut -d: -f2)" \
      "$(grep -m1 '^;PRINT_TIME_S:' "$out" | cut -d: -f2)" \
      "$(grep -m1 '^;FILAMENT_MM:' "$out" | cut -d: -f2)"
  done

  # CuraEngine 4.13.
  out=$work/cura-$layer.gcode
  cura_command "$layer" "$model" "$out"
  timed "${cura[@]}"
  row "CuraEngine 4.13" "$layer" "$(grep -c '^;LAYER:' "$out")" \
    "$(grep '^;TIME_ELAPSED:' "$out" | tail -1 | cut -d: -f2)" "$(filament_of "$out")"

  # PrusaSlicer 2.5.
  cfg=$work/prusa.ini
  cat >"$cfg" <<EOF
layer_height = $layer
bridge_speed = 30
support_material = 0
EOF
  out=$work/prusa-$layer.gcode
  timed prusa-slicer --export-gcode --load tests/bench/prusa_up_plus_2.ini --load "$cfg" --center 70,70 -o "$out" "$model"
  prusa_time=$(grep -m1 '^; estimated printing time (normal mode)' "$out" | sed 's/.*= //' |
    awk '{ s = 0; for (i = 1; i <= NF; i++) { v = $i + 0; u = substr($i, length($i));
           s += (u == "d") ? v * 86400 : (u == "h") ? v * 3600 : (u == "m") ? v * 60 : v } print s }')
  row "PrusaSlicer 2.5" "$layer" "$(grep -c '^;LAYER_CHANGE' "$out")" "$prusa_time" \
    "$(grep -m1 '^; filament used \[mm\]' "$out" | sed 's/.*= //')"
done

echo "bunny 50 mm, UP Plus 2 settings; each slicer's own print-time estimate; same machine, same run"
echo "wall, cpu and peak RSS: the run with the median wall time of $repeat"
printf '%-22s %5s %7s %13s %11s %10s %10s %11s\n' slicer layer layers "est. time" filament wall cpu "peak RSS"
printf '%s\n' "${rows[@]}"
for layer in 0.15 0.2; do
  for contour in best ma; do
    awk -v m="${walls["mahost ($contour) $layer"]}" -v cura="${walls["CuraEngine 4.13 $layer"]}" -v l="$layer" -v c="$contour" \
      'BEGIN { printf "mahost (%s) wall / CuraEngine wall at %s mm: %.2f\n", c, l, m / cura }'
  done
done
