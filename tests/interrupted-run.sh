#!/bin/sh
# pkm killed while writing an output leaves no temporary file, a signal ignored by its parent
# (nohup) stays ignored, and a temporary left by a run that could not clean up (SIGKILL) is named
# by the next run and removed.
# Usage: interrupted-run.sh PKM JOB.ngc WORK_DIRECTORY
set -u
pkm=$1 job=$2 dir=$3
rm -rf "$dir" && mkdir -p "$dir" && cd "$dir" || exit 1
fail() { echo "FAIL: $*"; ls -la; exit 1; }
# Until pkm has opened its output: the signal then lands in the middle of writing it.
wait_for_temporary() {
  tries=0
  until ls -A | grep -q '^\.out\.csv\.tmp-'; do
    tries=$((tries + 1))
    [ $tries -lt 200 ] || fail "no temporary file appeared"
    sleep 0.05
  done
}

# SIGTERM while the samples are being written (250,000 rows: over a second of work).
"$pkm" plan "$job" -o out.csv >/dev/null &
run=$!
wait_for_temporary
kill -TERM $run
wait $run
status=$?
[ $status -eq 143 ] || fail "pkm ended with status $status, not by SIGTERM (143)"
[ -z "$(ls -A)" ] || fail "files left after SIGTERM: $(ls -A)"

# A signal ignored when pkm starts (nohup's SIGHUP) stays ignored: the run goes on to the end.
sh -c 'trap "" HUP; exec "$0" plan "$1" -o out.csv >/dev/null' "$pkm" "$job" &
run=$!
wait_for_temporary
kill -HUP $run
wait $run
status=$?
[ $status -eq 0 ] || fail "pkm under nohup ended with status $status after SIGHUP"
[ -s out.csv ] || fail "no out.csv written under nohup"
rm out.csv

# A temporary from a killed run (its PID no longer runs) is named in a warning, and removed.
sh -c 'exit 0' & dead=$!
wait $dead
stale=".out.csv.tmp-$dead-AbCdEf"
head -c 2000000 /dev/zero >"$stale"
"$pkm" plan "$job" -o out.csv --period 0.01 >/dev/null 2>warnings.txt || fail "pkm plan failed"
cat warnings.txt
grep -q "warning: removed $stale (2 MB), a temporary file left by an interrupted run (pid $dead, no longer running)" warnings.txt ||
  fail "the warning does not name $stale"
[ ! -e "$stale" ] || fail "$stale is still there"
[ -s out.csv ] || fail "no out.csv written"
echo "ok"
