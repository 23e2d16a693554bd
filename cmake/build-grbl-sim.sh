#!/bin/sh
# Builds grbl-sim with ../shared's build-sim (cmake/GrblSim.cmake), then makes its step file
# line-buffered: grbl-sim writes the row of a block's end and its final row into a stdio buffer
# that is flushed only at exit, and its exit can stall (it cancels grbl's thread, which may hold
# a stdio lock), so a sender that has to kill it would lose the last rows: the very positions the
# tests compare.
# Second, its timer interrupts ignore the emulated interrupt flag (avr/interrupt.c,
# timer_interrupts). grbl-sim keeps the AVR's global interrupt flag in a plain variable that both
# its threads write: grbl's main loop (`sreg = SREG; cli(); ...; SREG = sreg;`, which it runs on
# every turn while its planner is full) and the simulated hardware entering an interrupt. A main
# thread taken off its core inside such a section held the stepper interrupt off while the clock
# ran on (runs of short blocks 10-35 % slow on a busy computer), and a restore of a value read
# during an interrupt left the flag off for good: grbl-sim froze mid-job, in Cycle, with SREG 0
# and timer 1's match pending (seen with gdb). On a board those sections last a few cycles, and
# grbl-sim's threads run in parallel anyway, so its cli never kept an interrupt out. Only
# grbl-sim's main.c and avr/interrupt.c change, nothing in grbl.
#   build-grbl-sim.sh BUILD_SIM DEST  ->  DEST/grbl/grbl-sim/grbl_sim.exe
set -eu
build_sim=$1
dest=$2
"$build_sim" "$dest" >/dev/null
cd "$dest/grbl/grbl-sim"
sed -i 's/^\([ \t]*\)args\.step_out_file = fopen(\*argv,"w");/&\n\1if (args.step_out_file) setvbuf(args.step_out_file, NULL, _IOLBF, 0);/' main.c
grep -q 'setvbuf(args.step_out_file' main.c || { echo "build-grbl-sim.sh: main.c not as expected" >&2; exit 1; }
sed -i 's/^\([ \t]*\)uint8_t ien = io\.sreg&SEI;.*$/\1uint8_t ien = SEI;  \/\* pkmkit: timers ignore the shared flag \*\//' avr/interrupt.c
grep -q 'uint8_t ien = SEI;' avr/interrupt.c || { echo "build-grbl-sim.sh: avr/interrupt.c not as expected" >&2; exit 1; }
make main >>build.log 2>&1 || { tail -20 build.log >&2; exit 1; }
echo "$dest/grbl/grbl-sim/grbl_sim.exe"
