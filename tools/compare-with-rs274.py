#!/usr/bin/env python3
"""Runs every G-code program under a directory through LinuxCNC's `rs274 -g` and `pkm gcode
--canon`, and says on how many of those rs274 accepts pkm gives the same motion.

    tools/compare-with-rs274.py [--pkm BUILD/apps/pkm/pkm] [--verbose] DIR|FILE...

Made for LinuxCNC's own interpreter tests (tests/interp/ in LinuxCNC's source, which is GPL and
so not in this repository): each program runs in a copy of its directory (rs274 writes its
parameter file there), with the tool table `test.tbl` and the INI file `test.ini` beside it when
there are (as the tests' test.sh scripts run them), else with the conformance test's tool table;
the INI's SUBROUTINE_PATH and ORIENT_OFFSET become pkm's --subroutine-path and --orient-offset. The motion is compared as
tests/test_gcode_conformance.cpp compares it: moves, dwells, taps, the spindle synchronisation
and the override locks (and the spindle inside those), numbers within one unit of the fourth
decimal. A program rs274 refuses (or runs for more than 20 s) is not counted.

Prints one line per program (`same`, `differs: ...`, `pkm refuses: ...`, `rs274 refuses`) and
the count: `identical on X of Y programs rs274 accepts`. Standard library only.
"""
import argparse
import configparser
import pathlib
import re
import shutil
import subprocess
import sys
import tempfile

HERE = pathlib.Path(__file__).resolve().parent
SOURCE = HERE.parent
CONFORMANCE_TABLE = SOURCE / "tests" / "conformance" / "conformance.tbl"
MOTION = ("STRAIGHT_TRAVERSE(", "STRAIGHT_FEED(", "STRAIGHT_PROBE(", "ARC_FEED(", "DWELL(",
          "RIGID_TAP(", "START_SPEED_FEED_SYNC(", "STOP_SPEED_FEED_SYNCH(",
          "ENABLE_SPEED_OVERRIDE(", "DISABLE_SPEED_OVERRIDE(", "ORIENT_SPINDLE(",
          "SPINDLE.0.WAIT_ORIENT_COMPLETE(")
LINE = re.compile(r"^\s*\d+ N\S*\s+(.*)$")


def motion(text):
    """The compared commands of a canonical listing (`rs274 -g` text)."""
    kept, locked = [], False
    for raw in text.splitlines():
        match = LINE.match(raw)
        if not match:
            continue
        command = match.group(1)
        if command.startswith("DISABLE_FEED_OVERRIDE("):
            locked = True
            kept.append(command)
        elif command.startswith("ENABLE_FEED_OVERRIDE("):
            locked = False
            kept.append(command)
        elif command.startswith(MOTION) or (
                locked and command.startswith(("START_SPINDLE_", "STOP_SPINDLE_"))):
            kept.append(command)
    return kept


def same_line(a, b):
    if a == b:
        return True
    name_a, _, args_a = a.partition("(")
    name_b, _, args_b = b.partition("(")
    if name_a != name_b:
        return False
    numbers_a, numbers_b = args_a.rstrip(")").split(","), args_b.rstrip(")").split(",")
    if len(numbers_a) != len(numbers_b):
        return False
    try:
        return all(abs(float(x) - float(y)) <= 1.01e-4 for x, y in zip(numbers_a, numbers_b))
    except ValueError:
        return False


def first_difference(reference, ours):
    for index, (a, b) in enumerate(zip(reference, ours)):
        if not same_line(a, b):
            return "move %d: rs274 %s, pkm %s" % (index + 1, a, b)
    if len(reference) != len(ours):
        return "rs274 moves %d times, pkm %d" % (len(reference), len(ours))
    return ""


def rs274ngc_settings(ini, directory):
    """pkm's options for what the INI's [RS274NGC] sets: SUBROUTINE_PATH, ORIENT_OFFSET."""
    parser = configparser.ConfigParser(strict=False, interpolation=None)
    try:
        parser.read(ini)
        paths = parser.get("RS274NGC", "SUBROUTINE_PATH", fallback="")
        offset = parser.get("RS274NGC", "ORIENT_OFFSET", fallback="")
    except configparser.Error:
        return []
    options = []
    paths = [str(directory / part.strip()) for part in paths.split(":") if part.strip()]
    if paths:
        options += ["--subroutine-path", ":".join(paths)]
    if offset.strip():
        options += ["--orient-offset", offset.strip()]
    return options


def run(program, pkm):
    """(verdict, detail): same, differs, pkm-refuses, rs274-refuses."""
    with tempfile.TemporaryDirectory(prefix="pkm-rs274-") as work:
        work = pathlib.Path(work)
        shutil.copytree(program.parent, work, dirs_exist_ok=True)
        table = work / "test.tbl" if (work / "test.tbl").exists() else CONFORMANCE_TABLE
        ini = work / "test.ini"
        rs274 = ["rs274", "-t", str(table)]
        pkm_command = [pkm, "gcode", "--canon", "--tool-table", str(table),
                       "--tool-table-units", "inch"]
        if ini.exists():
            rs274 += ["-i", str(ini)]
            pkm_command += rs274ngc_settings(ini, work)
        rs274 += ["-g", program.name]
        pkm_command.append(program.name)
        try:
            reference = subprocess.run(rs274, cwd=work, capture_output=True, text=True,
                                       timeout=20, stdin=subprocess.DEVNULL)
        except subprocess.TimeoutExpired:
            return "rs274-refuses", "runs for more than 20 s"
        if reference.returncode != 0:
            return "rs274-refuses", reference.stderr.strip().splitlines()[-1:] or ""
        ours = subprocess.run(pkm_command, cwd=work, capture_output=True, text=True, timeout=60)
        difference = first_difference(motion(reference.stdout), motion(ours.stdout))
        error = ours.stderr.strip().splitlines()[-1] if ours.returncode != 0 else ""
        if error:
            return "pkm-refuses", error
        if difference:
            return "differs", difference
        return "same", ""


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--pkm", default=str(SOURCE / "build" / "release" / "apps" / "pkm" / "pkm"))
    parser.add_argument("--verbose", action="store_true", help="also list the programs that match")
    parser.add_argument("paths", nargs="+")
    arguments = parser.parse_args()
    if shutil.which("rs274") is None:
        sys.exit("LinuxCNC's rs274 is not installed (scripts/setup installs linuxcnc-uspace)")
    programs = []
    for path in map(pathlib.Path, arguments.paths):
        programs += sorted(path.rglob("*.ngc")) if path.is_dir() else [path]
    counts = {}
    for program in programs:
        verdict, detail = run(program.resolve(), arguments.pkm)
        counts[verdict] = counts.get(verdict, 0) + 1
        if verdict != "same" or arguments.verbose:
            print("%-14s %s%s" % (verdict, program, ": %s" % detail if detail else ""))
    accepted = len(programs) - counts.get("rs274-refuses", 0)
    print("identical on %d of %d programs rs274 accepts (%d differ, %d refused by pkm; "
          "%d refused by rs274)" % (counts.get("same", 0), accepted, counts.get("differs", 0),
                                    counts.get("pkm-refuses", 0), counts.get("rs274-refuses", 0)))


if __name__ == "__main__":
    main()
