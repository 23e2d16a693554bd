#!/usr/bin/python3
"""Random jittery and back-and-forth jobs through `pkm post` (spanning) and `pkm verify` (issue 26).

A bad-input sweep found programs that post declared within the tolerance and verify refused, on
jobs whose moves jitter by micrometres or turn back along themselves. This script makes such jobs
on the example plotters and glides, posts each (spanning, and with --no-span-moves) and verifies
the result, and counts the jobs whose posted program fails verify.

  bench/span_sweep.py BUILD_DIR [--jobs 480] [--seed 26] [--keep DIR]

Prints one line per failing job (machine, tolerance, kind, seed, verify's message) and the counts.
Each job is made from its own seed, so a failing one can be made again alone (--only SEED).
"""
import argparse
import os
import random
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
MACHINES = os.path.join(os.path.dirname(HERE), "examples", "machines")

# Machine file, a centre of its work area in XY (mm), half the area's width, fixed Z.
PLACES = [
    ("hektor.toml", (35.0, -45.0), 15.0, None),
    ("wall-plotter.toml", (750.0, -700.0), 100.0, None),
    ("triaglide.toml", (0.0, 0.0), 40.0, 200.0),
    ("triaglide-fanned.toml", (0.0, 0.0), 40.0, 200.0),
]
TOLERANCES = [0.001, 0.01, 0.1]
KINDS = ["jitter", "back_and_forth", "doubling_back", "walk"]


def move(x, y, z):
    text = "G1 X%.6f Y%.6f" % (x, y)
    return text + (" Z%.3f" % z if z is not None else "")


def job_text(rng, kind, centre, half, z, tolerance):
    """A job of one kind: G-code text."""
    cx, cy = centre
    x = cx + rng.uniform(-0.5, 0.5) * half
    y = cy + rng.uniform(-0.5, 0.5) * half
    lines = ["G21 G90 G17", "G0 X%.6f Y%.6f%s" % (x, y, " Z%.3f" % z if z is not None else ""),
             "F%d" % rng.choice([300, 600, 1200])]
    count = rng.randint(3, 40)
    if kind == "back_and_forth":
        # Back and forth along one axis by a step of 0.1 to 10 tolerances (1 um at 0.001 mm),
        # between moves elsewhere.
        step = tolerance * rng.choice([0.1, 0.5, 1.0, 2.0, 10.0])
        for _ in range(rng.randint(1, 3)):
            x += rng.uniform(-1, 1) * half * 0.2
            y += rng.uniform(-1, 1) * half * 0.2
            lines.append(move(x, y, z))
            axis_x = rng.random() < 0.5
            for k in range(count):
                offset = step if k % 2 == 0 else 0.0
                lines.append(move(x + offset if axis_x else x, y if axis_x else y + offset, z))
    elif kind == "doubling_back":
        # Forward along a direction, back part of the way, forward again.
        for _ in range(count):
            dx, dy = rng.uniform(-1, 1), rng.uniform(-1, 1)
            norm = max(1e-9, (dx * dx + dy * dy) ** 0.5)
            length = rng.choice([tolerance, 10 * tolerance, 0.1, 1.0]) * rng.uniform(0.2, 1.0)
            for fraction in (1.0, -rng.uniform(0.1, 0.9), rng.uniform(0.5, 2.0)):
                x += fraction * length * dx / norm
                y += fraction * length * dy / norm
                lines.append(move(x, y, z))
    elif kind == "jitter":
        # A line in small steps, each vertex off it by up to a few tolerances.
        dx, dy = rng.uniform(-1, 1), rng.uniform(-1, 1)
        norm = max(1e-9, (dx * dx + dy * dy) ** 0.5)
        step = rng.choice([0.001, 0.01, 0.1, 0.5])
        amplitude = tolerance * rng.choice([0.5, 1.0, 3.0])
        for k in range(count * 3):
            bx = x + k * step * dx / norm
            by = y + k * step * dy / norm
            lines.append(move(bx + rng.uniform(-amplitude, amplitude),
                              by + rng.uniform(-amplitude, amplitude), z))
    else:  # walk: a random walk whose steps go any way, back included
        for _ in range(count * 3):
            step = rng.choice([0.001, 0.003, 0.01, 0.1, 1.0])
            x += rng.uniform(-step, step)
            y += rng.uniform(-step, step)
            lines.append(move(x, y, z))
    lines.append("M2")
    return "\n".join(lines) + "\n"


def run(pkm, args):
    result = subprocess.run([pkm] + args, capture_output=True, text=True)
    return result.returncode, (result.stdout + result.stderr).strip()


def one(pkm, directory, seed, span):
    rng = random.Random(seed)
    machine, centre, half, z = rng.choice(PLACES)
    tolerance = rng.choice(TOLERANCES)
    kind = rng.choice(KINDS)
    job = os.path.join(directory, "job%d.ngc" % seed)
    joints = os.path.join(directory, "job%d.%s.ngc" % (seed, "span" if span else "each"))
    with open(job, "w") as out:
        out.write(job_text(rng, kind, centre, half, z, tolerance))
    path = os.path.join(MACHINES, machine)
    post = ["post", "-m", path, job, "-o", joints, "--tolerance", str(tolerance)]
    code, text = run(pkm, post + ([] if span else ["--no-span-moves"]))
    if code != 0:
        return machine, tolerance, kind, "post refused", text.splitlines()[-1] if text else ""
    code, text = run(pkm, ["verify", "-m", path, joints, "--against", job])
    if code != 0:
        return machine, tolerance, kind, "verify failed", " | ".join(text.splitlines()[-3:])
    return machine, tolerance, kind, "ok", ""


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("build", help="the build directory (build/release)")
    parser.add_argument("--jobs", type=int, default=480)
    parser.add_argument("--seed", type=int, default=26)
    parser.add_argument("--only", type=int, help="make and run the job of this seed alone")
    parser.add_argument("--keep", help="write the jobs and programs here (default: a temporary)")
    parser.add_argument("--no-span-moves", action="store_true", help="post each move on its own")
    parser.add_argument("--pkm", help="the pkm binary (default: BUILD/apps/pkm/pkm)")
    args = parser.parse_args()
    pkm = args.pkm or os.path.join(args.build, "apps", "pkm", "pkm")
    seeds = [args.only] if args.only is not None else range(args.seed, args.seed + args.jobs)
    with tempfile.TemporaryDirectory() as temporary:
        directory = args.keep or temporary
        os.makedirs(directory, exist_ok=True)
        counts = {}
        for seed in seeds:
            machine, tolerance, kind, outcome, detail = one(pkm, directory, seed,
                                                            not args.no_span_moves)
            counts[outcome] = counts.get(outcome, 0) + 1
            if outcome != "ok":
                print("seed %d: %s tol %g %s: %s: %s" % (seed, machine, tolerance, kind, outcome,
                                                       detail))
                sys.stdout.flush()
    print(", ".join("%s %d" % item for item in sorted(counts.items())))
    return 0 if counts.get("verify failed", 0) == 0 else 1


if __name__ == "__main__":
    sys.exit(main())
