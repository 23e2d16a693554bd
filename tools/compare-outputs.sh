#!/usr/bin/env bash
# Runs two pkm binaries on the same inputs and says where their outputs differ: a check for a
# change meant to keep behaviour byte for byte (issue 28). For each example machine: `check
# --json`, the certified check of each example job (`check JOB --json`), `workspace --json`,
# `export linuxcnc --sim` (every file written), and `post` of each job (program and report).
# Usage: tools/compare-outputs.sh OLD_PKM NEW_PKM [WORKDIR]. Exit 1 when anything differs.
set -u
old=$1 new=$2 work=${3:-$(mktemp -d)}
root=$(cd "$(dirname "$0")/.." && pwd)
mkdir -p "$work/old" "$work/new"
differ=0 runs=0
# Lines that say how long a computation took (the joint-rate bound's seconds) differ run to run.
timing='^\(# Cells: \|joint-rate bound over \).* s\.\?$'

run() {  # run NAME ARGS...: both binaries, stdout+stderr+status into WORK/{old,new}/NAME
  local name=$1
  shift
  for side in old new; do
    local bin=$old
    [ "$side" = new ] && bin=$new
    local out="$work/$side/$name"
    mkdir -p "$out"
    (cd "$out" && timeout 300 "$bin" "$@" >stdout 2>stderr; echo $? >status)
  done
  runs=$((runs + 1))
  if ! diff -r -q -I "$timing" "$work/old/$name" "$work/new/$name" >/dev/null; then
    echo "DIFFERS: $name ($*)"
    differ=1
  fi
}
for machine in "$root"/examples/machines/*.toml; do
  m=$(basename "$machine" .toml)
  run "$m-check" check -m "$machine" --json
  run "$m-workspace" workspace -m "$machine" --json --threads 1
  run "$m-export" export linuxcnc -m "$machine" -o config --sim
  for job in "$root"/examples/jobs/*.ngc; do
    j=$(basename "$job" .ngc)
    run "$m-$j-certify" check "$job" -m "$machine" --json
    run "$m-$j-post" post "$job" -m "$machine" -o joints.ngc --report report.json
  done
done
echo "$runs runs compared in $work: $([ $differ = 0 ] && echo 'all identical' || echo 'some differ')"
exit $differ
