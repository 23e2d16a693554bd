#!/bin/sh
# `pkm gcode --canon` against LinuxCNC's `rs274 -g` as whole commands (issue 16): the CPU time
# (user + system, perf stat's task-clock, mean of RUNS runs) of each on the same programs, output
# to /dev/null, run one after the other in this script so that both see the same machine. rs274
# is a command run beside pkm; no LinuxCNC code is involved.
#
#   bench/canon_vs_rs274.sh [PROGRAM...]
#
# Defaults: the real corpus's stellabee1.ngc (169k lines). PKM names the pkm to time (default
# build/release/apps/pkm/pkm), BEFORE another pkm to time beside it (an older build, say), RUNS
# the runs per mean (default 10). Needs perf (linux-perf) and rs274 (linuxcnc-uspace).
set -eu
here=$(cd "$(dirname "$0")/.." && pwd)
pkm=${PKM:-$here/build/release/apps/pkm/pkm}
runs=${RUNS:-10}
[ $# -gt 0 ] || set -- "$here/../shared/gcode/real/linuxcnc/stellabee1.ngc"
for tool in perf rs274; do
  command -v $tool >/dev/null || { echo "canon_vs_rs274: $tool is not installed" >&2; exit 2; }
done
[ -x "$pkm" ] || { echo "canon_vs_rs274: no pkm at $pkm (build it, or set PKM)" >&2; exit 2; }

# The mean CPU time of a command in ms.
cpu_ms() {
  perf stat -x, -e task-clock -r "$runs" "$@" 2>&1 >/dev/null | awk -F, '/task-clock/ {print $1}'
}

for program in "$@"; do
  [ -f "$program" ] || { echo "canon_vs_rs274: no program $program" >&2; exit 2; }
  lines=$(wc -l <"$program")
  rs274_ms=$(cpu_ms rs274 -g "$program")
  pkm_ms=$(cpu_ms "$pkm" gcode --canon "$program")
  echo "$(basename "$program") ($lines lines), CPU ms, mean of $runs runs:"
  printf '  rs274 -g          %9.1f ms\n' "$rs274_ms"
  printf '  pkm gcode --canon %9.1f ms   %.1fx faster than rs274\n' "$pkm_ms" \
    "$(awk "BEGIN {print $rs274_ms / $pkm_ms}")"
  if [ -n "${BEFORE:-}" ]; then
    before_ms=$(cpu_ms "$BEFORE" gcode --canon "$program")
    printf '  before (%s) %9.1f ms   %.1fx faster than rs274\n' "$(basename "$BEFORE")" \
      "$before_ms" "$(awk "BEGIN {print $rs274_ms / $before_ms}")"
  fi
done
