#!/bin/sh
# Writes tests/data/delta-measurements.csv: what a probe would record on a linear delta built
# off its machine file (examples/machines/linear-delta.toml) by known amounts:
#   rail 2 (tower_b): strut 301.2 mm instead of 300 mm
#   rail 3 (tower_c): origin z 0.8 mm instead of 0 (its carriage sits 0.8 mm higher at a reading)
# At 30 tool positions over the workspace (x y within 110 mm of the axis, z 20..280 mm) it
# records the built machine's joint readings (`pkm ik`, rounded to 0.001 mm) beside the position.
# `pkm calibrate fit -m linear-delta.toml delta-measurements.csv --params
# 'rail*.strut,rail*.origin.z'` must recover the two amounts (tests/CMakeLists.txt,
# cli.firmware_calibrated_delta_*; docs/firmware.md "Calibration to firmware").
#
# usage: tools/make-delta-measurements.sh PKM LINEAR_DELTA_TOML OUTPUT_CSV
set -eu
pkm=$1
nominal=$2
output=$3
built=$(mktemp "${TMPDIR:-/tmp}/built-delta.XXXXXX")
trap 'rm -f "$built"' EXIT

# The built machine: the nominal file with the second rail's strut and the third rail's origin
# changed (rails counted by their [[kinematics.rails]] headers).
awk '
  /^\[\[kinematics\.rails\]\]/ { rail++ }
  rail == 2 && /^strut = / { $0 = "strut = 301.2" }
  rail == 3 && /^origin = / { $0 = "origin = [173.20508075688772, -100.0, 0.8]" }
  { print }
' "$nominal" >"$built"
grep -q '^strut = 301.2$' "$built" && grep -q '0\.8\]$' "$built" || {
  echo "$0: $nominal: no rails to change (has the file's layout changed?)" >&2
  exit 1
}

echo "j_tower_a,j_tower_b,j_tower_c,x,y,z" >"$output.tmp"
for z in 20 150 280; do
  # the axis, four points at 60 mm and five at 110 mm from it, turned a little at each height
  for xy in "0 0" "60 0" "0 60" "-60 0" "0 -60" \
            "110 0" "34 104.6" "-89 64.7" "-89 -64.7" "34 -104.6"; do
    set -- $xy
    x=$1
    y=$2
    if [ "$z" = 150 ]; then t=$x; x=$y; y=$(echo "$t" | awk '{ print -$1 }'); fi
    joints=$("$pkm" ik -m "$built" "$x" "$y" "$z" --json)
    echo "$joints" | awk -v x="$x" -v y="$y" -v z="$z" '{
      sub(/.*"joints":\[/, ""); sub(/\].*/, ""); n = split($0, j, ",")
      printf "%.3f,%.3f,%.3f,%.3f,%.3f,%.3f\n", j[1], j[2], j[3], x, y, z
    }' >>"$output.tmp"
  done
done
mv "$output.tmp" "$output"
