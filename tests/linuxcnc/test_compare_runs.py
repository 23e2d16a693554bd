#!/usr/bin/python3
"""run-differential's sample-by-sample comparison on small made-up runs (no LinuxCNC needed):
it passes two runs that differ by rounding only and by their samples at rest, and fails a joint
1.02e-6 mm off in one sample, a commanded pose that parts, an extra servo cycle of motion, and
a sample in another motion mode. Exit status 0 when every case gives the verdict it should."""
import contextlib
import csv
import importlib.machinery
import importlib.util
import io
import os
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
HEADER = ["enabled", "all_homed", "coord", "teleop", "line", "x", "y", "z", "j0", "j1"]


def load_run_differential():
    loader = importlib.machinery.SourceFileLoader("run_differential",
                                                  os.path.join(HERE, "run-differential"))
    spec = importlib.util.spec_from_loader("run_differential", loader)
    module = importlib.util.module_from_spec(spec)
    loader.exec_module(module)
    return module


def motion_rows(rest_at_start):
    """A homed run (inch): rest, a joint-mode step, then a line in coordinated mode, rest."""
    rows = [[1, 1, 0, 0, 0, 0.0, 0.0, 20.0, 30.0, 30.0]] * rest_at_start
    rows += [[1, 1, 0, 0, 0, 0.0, 0.0, 20.0 + 1e-4 * k, 30.0 + 1e-4 * k, 30.0] for k in range(1, 4)]
    rows += [[1, 1, 1, 0, 3, 0.01 * k, 0.0, 20.0003, 30.0003 + 0.003 * k, 30.0 - 0.002 * k]
             for k in range(1, 50)]
    return rows + [rows[-1]] * 7


def write_run(directory, rows):
    os.makedirs(directory)
    with open(os.path.join(directory, "samples.csv"), "w", newline="") as out:
        writer = csv.writer(out, lineterminator="\n")
        writer.writerow(HEADER)
        for row in rows:
            writer.writerow([repr(v) if isinstance(v, float) else v for v in row])


def verdict(module, work, name, rows):
    write_run(os.path.join(work, name), rows)
    with contextlib.redirect_stdout(io.StringIO()) as said:
        ok = module.compare_runs(os.path.join(work, "reference"), os.path.join(work, name),
                                 "inch", [], 1e-6)
    return ok, said.getvalue()


def main():
    module = load_run_differential()
    work = tempfile.mkdtemp(prefix="pkmkit-compare-runs-")
    write_run(os.path.join(work, "reference"), motion_rows(rest_at_start=12))
    rounding = [row[:5] + [v + 1e-13 for v in row[5:]] for row in motion_rows(rest_at_start=40)]
    joint_off = [list(row) for row in motion_rows(rest_at_start=3)]
    joint_off[30][8] += 4e-8  # in: 1.016e-6 mm
    pose_parts = [list(row) for row in motion_rows(rest_at_start=3)]
    pose_parts[30][5] += 1e-6
    extra_cycle = motion_rows(rest_at_start=3)
    extra_cycle.insert(20, [1, 1, 1, 0, 3, 0.005, 0.0, 20.0003, 30.0003, 30.0])
    other_mode = [list(row) for row in motion_rows(rest_at_start=3)]
    other_mode[10][2] = 0
    cases = [("rounding and rest", rounding, True, "sample by sample: pass"),
             ("a joint 1.02e-6 mm off", joint_off, False, "worst joint difference: 1.02e-06 mm"),
             ("a pose that parts", pose_parts, False, "worst pose difference: 2.54e-05 mm"),
             ("an extra cycle", extra_cycle, False, "the commanded poses part at moving sample"),
             ("another motion mode", other_mode, False, "1 samples in different motion modes")]
    failures = 0
    for name, rows, expected, says in cases:
        ok, said = verdict(module, work, name.replace(" ", "_"), rows)
        right = ok == expected and says in said
        failures += not right
        print("%s: %s %s" % ("ok" if right else "WRONG", name, "passes" if ok else "fails"))
        if not right:
            print(said)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
