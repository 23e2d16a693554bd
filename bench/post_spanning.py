#!/usr/bin/python3
"""How many joint-space blocks a covering that may span programmed moves would save (issue 16).

`pkm post` covers each programmed move on its own: at least one joint-linear block per move. A
covering may instead let one block run across several short straight moves when the block stays
within the tolerance of the programmed polyline. This script estimates the saving on real plotter
drawings before anything is built:

  1. `pkm post` gives today's block count (its report).
  2. `pkm gcode --canon` gives the programmed moves; runs of feed moves at one height (the pen
     down, no rapid between them) are the paths a block may span: straight feeds only, and
     straight feeds and arcs (each arc as points every 2 degrees).
  3. Greedily from each run's first vertex, the block goes to the furthest vertex whose
     joint-linear path (FK at 64 points, pkmkit from Python) and the polyline lie within the
     tolerance of each other both ways (sampled Hausdorff distance: the most favourable test for
     spanning, so the saving found is an upper bound on what a proven covering could save).
  4. Every span of k moves saves k - 1 blocks of today's count (each of those moves took exactly
     one block today: a move that needs more than one is never spanned). Arcs' points and the
     64 FK points are samples: the ratio is an estimate, not a bound.

  bench/post_spanning.py BUILD_DIR [--tolerance MM]

Prints per drawing: moves, today's blocks, blocks with spanning (lines only; lines and arcs),
the ratios. The issue asks to build
spanning only if it saves 1.5x or more.

Its test is the sampled distance both ways, not the order of the path, so its spans may turn
back on themselves; post's never do (docs/post.md, "No span across a turn back"), which keeps the
estimate an upper bound.

It was built (docs/post.md, "Spanning moves"), on by default; step 1 asks `pkm post` for one
covering per move (--no-span-moves). bench/bench_post measures the built covering both ways.
"""
import argparse
import json
import os
import re
import subprocess
import sys
import tempfile

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
SOURCE = os.path.dirname(HERE)
CORPUS = os.path.join(os.path.dirname(SOURCE), "shared", "gcode", "real")
MACHINES = os.path.join(SOURCE, "examples", "machines")

# The drawings of the real corpus and where tests/test_real_jobs.cpp places them.
DRAWINGS = [
    ("plotter/inkscape/mandala_cnc_0001.gcode", "linuxcnc-polargraph-2366.toml", (1130, -1200)),
    ("plotter/dexarm-inkscape/vitruvianMan.gcode", "linuxcnc-polargraph-2366.toml", (1150, -1100)),
    ("plotter/svg2gcode/smooth_curves_circular_interpolation.gcode",
     "linuxcnc-polargraph-2366.toml", (1000, -1200)),
    # Two more of about the mandala's size (100 to 135 mm), placed where it is.
    ("plotter/inkscape/btc_laser_qr_unbt_0001.gcode", "linuxcnc-polargraph-2366.toml",
     (1130, -1200)),
    ("plotter/camotics/la_peinture.gc", "linuxcnc-polargraph-2366.toml", (1130, -1200)),
]
MOVE = re.compile(r"(STRAIGHT_FEED|STRAIGHT_TRAVERSE|ARC_FEED)\(([^)]*)\)")
SAMPLES = 64


def arc_points(start, end, centre, rotation):
    """Points along an XY arc from start to end about centre (rotation > 0 counter-clockwise,
    |rotation| turns), every 2 degrees or closer."""
    a0 = np.arctan2(start[1] - centre[1], start[0] - centre[0])
    a1 = np.arctan2(end[1] - centre[1], end[0] - centre[0])
    sweep = a1 - a0
    if rotation > 0:
        while sweep <= 1e-12:
            sweep += 2 * np.pi
        sweep += 2 * np.pi * (rotation - 1)
    else:
        while sweep >= -1e-12:
            sweep -= 2 * np.pi
        sweep -= 2 * np.pi * (-rotation - 1)
    radius = np.hypot(start[0] - centre[0], start[1] - centre[1])
    count = max(2, int(abs(sweep) / np.radians(2.0)) + 1)
    angles = a0 + sweep * np.linspace(0.0, 1.0, count)
    points = np.column_stack([centre[0] + radius * np.cos(angles),
                              centre[1] + radius * np.sin(angles)])
    points[-1] = end
    return points


def runs_of_feeds(pkm, job, origin, with_arcs):
    """Runs of consecutive feed moves at one Z (the pen down), each a list of the moves' paths
    (arrays of machine XY points, mm, from the move's start to its end). Arcs join runs only
    `with_arcs`."""
    text = subprocess.run([pkm, "gcode", "--canon", job], capture_output=True, text=True,
                          check=True).stdout
    runs, current, at, at_z = [], [], None, None
    for kind, args in MOVE.findall(text):
        values = [float(v) for v in args.split(",")]
        end = np.array([values[0] + origin[0], values[1] + origin[1]])
        z = values[5] if kind == "ARC_FEED" else values[2]
        joins = kind == "STRAIGHT_FEED" or (kind == "ARC_FEED" and with_arcs)
        if joins and at is not None and z == at_z:
            if kind == "ARC_FEED":
                centre = (values[2] + origin[0], values[3] + origin[1])
                current.append(arc_points(at, end, centre, int(values[4])))
            else:
                current.append(np.array([at, end]))
        else:
            if current:
                runs.append(current)
            current = []
        at, at_z = end, z
    if current:
        runs.append(current)
    return runs


def point_to_polyline(points, polyline):
    """Distance of each point to the polyline (segments between consecutive vertices)."""
    a, b = polyline[:-1], polyline[1:]
    ab = b - a
    length2 = np.maximum((ab * ab).sum(axis=1), 1e-300)
    ap = points[:, None, :] - a[None, :, :]
    t = np.clip((ap * ab[None]).sum(axis=2) / length2[None], 0.0, 1.0)
    closest = a[None] + t[..., None] * ab[None]
    return np.sqrt(((points[:, None, :] - closest) ** 2).sum(axis=2)).min(axis=1)


def spans(machine, run, tolerance):
    """Greedy spans over one run of moves: the number of moves each block covers."""
    vertices = np.array([run[0][0]] + [path[-1] for path in run])
    joints, status = machine.inverse(vertices)
    if not all(s == "ok" for s in status):
        return [1] * len(run)
    lam = np.linspace(0.0, 1.0, SAMPLES)[:, None]

    def fits(i, j):
        path = joints[i] + lam * (joints[j] - joints[i])
        traced, ok = machine.forward(path)
        if not all(s == "ok" for s in ok):
            return False
        programmed = np.concatenate(run[i:j])
        there = point_to_polyline(traced, programmed).max()
        back = point_to_polyline(programmed, traced).max()
        return max(there, back) <= tolerance

    result, i = [], 0
    while i < len(run):
        j = i + 1
        if fits(i, j):
            while j < len(run) and fits(i, j + 1):
                j += 1
        result.append(j - i)
        i = j
    return result


def readable_job(path, scratch):
    """The job as the tests read it (tests/real_job_copy.hpp): a DexArm header's firmware modes
    (M2000, M888), which pkm refuses at their column, blanked so every other line keeps its
    number."""
    if "dexarm" not in path:
        return path
    copy = os.path.join(scratch, os.path.basename(path))
    with open(path) as original, open(copy, "w") as out:
        for line in original:
            out.write("\n" if line.startswith(("M2000", "M888")) else line)
    return copy


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("build")
    parser.add_argument("--tolerance", type=float, default=0.01)
    args = parser.parse_args()
    sys.path.insert(0, os.path.join(args.build, "python"))
    import pkmkit  # noqa: E402 (the build's module)

    pkm = os.path.join(args.build, "apps", "pkm", "pkm")
    print("%-40s %7s %8s %9s %6s %9s %6s" % ("drawing", "moves", "blocks", "lines", "ratio",
                                             "and arcs", "ratio"))
    for job, machine_file, origin in DRAWINGS:
        machine_path = os.path.join(MACHINES, machine_file)
        with tempfile.TemporaryDirectory() as scratch:
            path = readable_job(os.path.join(CORPUS, job), scratch)
            report_path = os.path.join(scratch, "report.json")
            subprocess.run([pkm, "post", "-m", machine_path, path, "--origin", str(origin[0]),
                            str(origin[1]), "0", "--tolerance", str(args.tolerance), "--no-span-moves", "-o",
                            os.path.join(scratch, "out.ngc"), "--report", report_path],
                           check=True, capture_output=True)
            report = json.load(open(report_path))
            machine = pkmkit.Machine.load(machine_path)
            blocks = report["blocks"]
            row = [os.path.basename(job)[:40], report["moves"], blocks]
            for with_arcs in (False, True):
                saved = 0
                for run in runs_of_feeds(pkm, path, origin, with_arcs):
                    saved += sum(k - 1 for k in spans(machine, run, args.tolerance))
                row += [blocks - saved, blocks / (blocks - saved)]
        print("%-40s %7d %8d %9d %6.3f %9d %6.3f" % tuple(row))


if __name__ == "__main__":
    main()
