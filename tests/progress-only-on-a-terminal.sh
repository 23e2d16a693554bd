#!/bin/sh
# post and verify draw a progress bar on a terminal only: on a file or a pipe stderr stays empty;
# under script(1) (a terminal) the bar shows (at once, with PKM_PROGRESS_AFTER_MS=0) and is cleared
# before the summary. The post of the hyperboloid at 0.001 mm takes some 1.5 s.
# Usage: progress-only-on-a-terminal.sh PKM JOB.ngc WORK_DIRECTORY
set -u
pkm=$1 job=$2 dir=$3
rm -rf "$dir" && mkdir -p "$dir" && cd "$dir" || exit 1
fail() { echo "FAIL: $*"; exit 1; }

"$pkm" post "$job" -o joints.ngc --tolerance 0.001 >out.txt 2>err.txt || fail "post failed"
[ ! -s err.txt ] || fail "post wrote to stderr on a file: $(cat -v err.txt)"
"$pkm" verify joints.ngc --against "$job" 2>&1 >/dev/null | cat >err.txt || fail "verify failed"
[ ! -s err.txt ] || fail "verify wrote to stderr on a pipe: $(cat -v err.txt)"

if ! command -v script >/dev/null; then
  echo "no script(1) here: the bar on a terminal is not tried"
  exit 0
fi
# The bar is drawn from the start here, so a fast machine cannot finish before it shows.
PKM_PROGRESS_AFTER_MS=0 script -qec "'$pkm' post '$job' -o joints.ngc --tolerance 0.001" \
  /dev/null >tty.txt ||
  fail "post under script failed"
grep -q 'pkm post hyperboloid\.ngc \[=* *\] *[0-9]*%  line [0-9]* of [0-9]*' tty.txt ||
  fail "no progress bar on a terminal: $(cat -v tty.txt)"
# The bar is cleared (a carriage return, blanks, a carriage return) before the summary.
tr '\r' '\n' <tty.txt | grep -q '^ *$' || fail "the bar is not cleared: $(cat -v tty.txt)"
tr '\r' '\n' <tty.txt | grep -q '^joints\.ngc: [0-9]* blocks' ||
  fail "no summary after the bar: $(cat -v tty.txt)"
echo "progress bar on a terminal only"
