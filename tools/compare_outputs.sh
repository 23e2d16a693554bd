#!/usr/bin/env bash
# Runs two pkm binaries over the same commands (`pkm gcode --canon` on real jobs of
# /work/shared/gcode/real or GCODE_CORPUS, `pkm plan` CSV, NPY, estimates and JSON reports on the
# example machines and jobs; for every example machine `check --json`, `workspace --json`, `export
# linuxcnc --sim`, and each example job's certified check and post) and compares every output byte for byte: stdout, stderr, exit status
# and the files written. For refactors that must not change behaviour (docs/decisions.md).
#
#   tools/compare_outputs.sh BEFORE_PKM AFTER_PKM [WORK_DIR]
#
# Exit status 0 when every output is identical; the differing files are listed otherwise.
set -euo pipefail

before=$(realpath "$1")
after=$(realpath "$2")
work=${3:-$(mktemp -d)}
repo=$(cd "$(dirname "$0")/.." && pwd)
corpus=${GCODE_CORPUS:-/work/shared/gcode/real}
machines=$repo/examples/machines
jobs=$repo/examples/jobs

# Each case: a name, then pkm's arguments; OUT in them stands for the case's output directory.
cases=()
add() { cases+=("$*"); }
for job in linuxcnc/3D_Chips.ngc linuxcnc/arcspiral.ngc linuxcnc/tort.ngc linuxcnc/flowsnake.ngc \
  linuxcnc/useful-subroutines.ngc linuxcnc/polar.ngc linuxcnc/cds.ngc linuxcnc-5axis/boat-xyzac.ngc \
  grbl/braid_cut2d.nc grbl/8x_gear_test.nc; do
  [[ -f $corpus/$job ]] && add "canon-${job//\//-}" gcode --canon "$corpus/$job"
done
add plan-hexapod-hyperboloid plan -m "$machines/hexapod-bit.toml" "$jobs/hyperboloid.ngc" \
  --period 0.005 -o OUT/samples.csv --report OUT/report.json
add plan-hexapod-sphere-npy plan -m "$machines/hexapod-bit.toml" "$jobs/sphere.ngc" -o OUT/samples.npy
add plan-hexapod-sphere-jerk plan -m "$machines/hexapod-bit.toml" "$jobs/sphere.ngc" --jerk 5000 \
  --period 0.004 -o OUT/samples.csv
add plan-hexapod-great-circle plan -m "$machines/hexapod-bit.toml" "$jobs/hyperboloid.ngc" \
  --attitude great-circle --estimate --report OUT/report.json
add plan-triaglide-hyperboloid plan -m "$machines/triaglide.toml" "$jobs/hyperboloid.ngc" \
  --jerk 2000 --period 0.01 -o OUT/samples.csv --report OUT/report.json
add plan-hexaglide-drawing plan -m "$machines/hexaglide.toml" "$jobs/first-drawing.ngc" \
  -o OUT/samples.csv --report OUT/report.json
add plan-makelangelo-drawing plan -m "$machines/makelangelo.toml" "$jobs/first-drawing.ngc" \
  -o OUT/samples.csv --report OUT/report.json
add plan-wall-plotter-drawing plan -m "$machines/wall-plotter.toml" "$jobs/first-drawing.ngc" \
  --origin 720 -1011 -o OUT/samples.csv --report OUT/report.json
add plan-hektor-drawing plan -m "$machines/hektor.toml" "$jobs/first-drawing.ngc" \
  --origin 20 -116 -o OUT/samples.csv --report OUT/report.json
add plan-maslow-drawing plan -m "$machines/maslow.toml" "$jobs/first-drawing.ngc" \
  --origin 1459 -1536 -12 -o OUT/samples.csv --report OUT/report.json
add plan-hexapod-drawing-error plan -m "$machines/hexapod-bit.toml" "$jobs/first-drawing.ngc" --estimate
add plan-hexapod-max-samples plan -m "$machines/hexapod-bit.toml" "$jobs/sphere.ngc" \
  --max-samples 1000 -o OUT/samples.csv
# Real jobs, placed where `pkm check` says they are centred in the hexapod's reach.
hexapod_real() {  # name, job, x y z origin, pkm plan's options
  local name=$1 job=$2 x=$3 y=$4 z=$5
  shift 5
  [[ -f $corpus/$job ]] && add "plan-hexapod-$name" plan -m "$machines/hexapod-bit.toml" \
    "$corpus/$job" --origin "$x" "$y" "$z" "$@"
}
hexapod_real arcspiral linuxcnc/arcspiral.ngc -35 13 970 --period 0.01 -o OUT/samples.csv \
  --report OUT/report.json
hexapod_real tort linuxcnc/tort.ngc -22 -14 971 --period 0.01 -o OUT/samples.npy
hexapod_real daisy linuxcnc/daisy.ngc -13 0 981 --jerk 20000 -o OUT/samples.csv
hexapod_real trochoidal linuxcnc/trochoidal.ngc -26 -54 979 --period 0.01 -o OUT/samples.csv \
  --report OUT/report.json
hexapod_real gear-estimate grbl/8x_gear_test.nc -28 -15 982 --estimate --report OUT/report.json
hexapod_real 3dtest-estimate linuxcnc/3dtest.ngc -39 -25 959 --estimate
# LinuxCNC exports: their summary quotes the planner's feed along each axis (plan_speed_along).
for machine in triaglide hexapod-bit hexaglide linear-delta linuxcnc-rdelta; do
  add "export-linuxcnc-$machine" export linuxcnc -m "$machines/$machine.toml" -o OUT/config
done

# Every example machine: its check, its workspace, its LinuxCNC export, and each example job's
# certified check and post (program and report).
for machine_file in "$machines"/*.toml; do
  m=$(basename "$machine_file" .toml)
  add "check-$m" check -m "$machine_file" --json
  add "workspace-$m" workspace -m "$machine_file" --json --threads 1
  add "export-sim-$m" export linuxcnc -m "$machine_file" -o OUT/config --sim
  for job in "$jobs"/*.ngc; do
    j=$(basename "$job" .ngc)
    add "certify-$m-$j" check "$job" -m "$machine_file" --json
    add "post-$m-$j" post "$job" -m "$machine_file" -o OUT/joints.ngc --report OUT/report.json
  done
done

run_all() {  # binary, directory
  local binary=$1 root=$2
  for entry in "${cases[@]}"; do
    read -r -a words <<<"$entry"
    local name=${words[0]} dir=$root/${words[0]}
    mkdir -p "$dir"
    local args=("${words[@]:1}")
    args=("${args[@]//OUT/$dir}")
    set +e
    (cd "$dir" && "$binary" "${args[@]}" >stdout 2>stderr)
    echo $? >"$dir/status"
    set -e
    # The paths differ between the two runs: written relative to the case's directory.
    sed -i "s#$dir#OUT#g" "$dir/stdout" "$dir/stderr"
    # The LinuxCNC export reports how long its bound took: the one output that is a measurement.
    find "$dir" -type f \( -name stdout -o -name '*.ini' \) -exec sed -i -E \
      -e 's/(cells), [0-9.]+ s$/\1, TIME s/' -e 's/(volume); [0-9.]+ s\.$/\1; TIME s./' \
      -e 's/^(# Cells: .*) [0-9.]+ s\.?$/\1 TIME s/' {} +
    echo "$name: exit $(cat "$dir/status")" >&2
  done
}

run_all "$before" "$work/before"
run_all "$after" "$work/after"
if diff -rq "$work/before" "$work/after"; then
  echo "identical: ${#cases[@]} cases, $(find "$work/before" -type f | wc -l) files ($work)"
else
  echo "outputs differ ($work)" >&2
  exit 1
fi
