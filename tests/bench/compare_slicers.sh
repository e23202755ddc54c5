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

# Runs a command $repeat times under /usr/bin/time; leaves the figures "wall_s user_s sys_s
# peak_kib" of the run with the median wall time in $work/time (CPU time, user + system over
# all threads, is what a busy machine does not inflate).
timed() {
  : >"$work/times"
  for ((run = 0; run < repeat; run++)); do
    /usr/bin/time -f "%e %U %S %M" -o "$work/time" "$@" >"$work/log" 2>&1 || {
      echo "compare_slicers: failed: $*" >&2; tail -5 "$work/log" >&2; exit 1; }
    cat "$work/time" >>"$work/times"
  done
  sort -n "$work/times" | sed -n "$(((repeat + 1) / 2))p" >"$work/time"
}

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
bed_shape = 0x0,140x0,140x140,0x140
max_print_height = 135
nozzle_diameter = 0.4
filament_diameter = 1.75
layer_height = $layer
first_layer_height = 0.3
extrusion_width = 0.45
first_layer_extrusion_width = 0.5
perimeters = 2
fill_density = 20%
fill_pattern = grid
top_solid_layers = 3
bottom_solid_layers = 3
skirts = 1
skirt_distance = 3
brim_width = 0
support_material = 0
external_perimeter_speed = 25
perimeter_speed = 40
small_perimeter_speed = 25
infill_speed = 50
solid_infill_speed = 40
top_solid_infill_speed = 30
gap_fill_speed = 25
bridge_speed = 30
travel_speed = 120
first_layer_speed = 15
retract_length = 1
retract_speed = 30
deretract_speed = 25
retract_before_travel = 2
gcode_flavor = marlin2
machine_limits_usage = time_estimate_only
machine_max_acceleration_extruding = 800
machine_max_acceleration_travel = 1500
machine_max_acceleration_retracting = 2000
machine_max_acceleration_x = 1500
machine_max_acceleration_y = 1500
machine_max_acceleration_z = 100
machine_max_acceleration_e = 3000
machine_max_feedrate_x = 200
machine_max_feedrate_y = 200
machine_max_feedrate_z = 10
machine_max_feedrate_e = 40
temperature = 245
first_layer_temperature = 250
bed_temperature = 100
first_layer_bed_temperature = 105
filament_density = 1.04
cooling = 0
fan_always_on = 0
start_gcode = G28
end_gcode = M84
EOF
  out=$work/prusa-$layer.gcode
  timed prusa-slicer --export-gcode --load "$cfg" --center 70,70 -o "$out" "$model"
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
