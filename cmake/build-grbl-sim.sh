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
# grbl-sim's threads run in parallel anyway, so its cli never kept an interrupt out.
# Third, its serial output. grbl's serial_write stores the byte, then advances the ring buffer's
# head (not volatile), then sets the transmit interrupt's enable bit, while grbl-sim's other
# thread runs the transmit interrupt: at -O3 the head may be stored before the byte, and the
# enable bit, set again just after the interrupt sent the last byte and cleared it, makes the
# interrupt send from an empty ring. Either way one stale byte goes out instead of the new one:
# a status report came as "...|FS:0,0|\nn:PXYZRHS|..." on a busy computer (its 'P' lost). grbl's
# serial.c is compiled at -O0 (its stores in program order, which x86 keeps between threads),
# and the emulated transmitter sends only while the ring holds a byte, as the UART's interrupt
# never fires between grbl's two instructions on a board. Only grbl-sim's main.c, serial.c,
# avr/interrupt.c and Makefile change, nothing in grbl.
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
sed -i 's/^\(\t\$(COMPILE) -include serial_hooks.h -c \$< -o \$@\)$/\1 -O0/' Makefile
grep -q 'serial_hooks.h -c $< -o $@ -O0' Makefile || { echo "build-grbl-sim.sh: Makefile not as expected" >&2; exit 1; }
sed -i 's/^\([ \t]*\)while (UCSR0B & (1<<UDRIE0)){$/extern uint8_t serial_tx_buffer_head; extern volatile uint8_t serial_tx_buffer_tail;\n&\n\1  if (serial_tx_buffer_tail == *(volatile uint8_t*)\&serial_tx_buffer_head) break;  \/\* pkmkit: nothing to send \*\//' serial.c
grep -q 'pkmkit: nothing to send' serial.c || { echo "build-grbl-sim.sh: serial.c not as expected" >&2; exit 1; }
rm -f ../serial.o serial.o
make main >>build.log 2>&1 || { tail -20 build.log >&2; exit 1; }
echo "$dest/grbl/grbl-sim/grbl_sim.exe"
