#!/bin/sh
# Builds grbl-sim with ../shared's build-sim (cmake/GrblSim.cmake), then makes its step file
# line-buffered: grbl-sim writes the row of a block's end and its final row into a stdio buffer
# that is flushed only at exit, and its exit can stall (it cancels grbl's thread, which may hold
# a stdio lock), so a sender that has to kill it would lose the last rows: the very positions the
# tests compare. Only grbl-sim's main.c changes, nothing in grbl.
#   build-grbl-sim.sh BUILD_SIM DEST  ->  DEST/grbl/grbl-sim/grbl_sim.exe
set -eu
build_sim=$1
dest=$2
"$build_sim" "$dest" >/dev/null
cd "$dest/grbl/grbl-sim"
sed -i 's/^\([ \t]*\)args\.step_out_file = fopen(\*argv,"w");/&\n\1if (args.step_out_file) setvbuf(args.step_out_file, NULL, _IOLBF, 0);/' main.c
grep -q 'setvbuf(args.step_out_file' main.c || { echo "build-grbl-sim.sh: main.c not as expected" >&2; exit 1; }
make main >>build.log 2>&1 || { tail -20 build.log >&2; exit 1; }
echo "$dest/grbl/grbl-sim/grbl_sim.exe"
