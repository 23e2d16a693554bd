#!/usr/bin/python3
"""Batch kinematics from Python (the pkmkit module, docs/python.md): ns per pose for IK and FK
over a million poses, against the C++ figure, and the binding's overhead per call, for a few
example machines; each the best of three (timeit).

The C++ figure is bench_kinematics' `inverse/NAME` and `forward_from_home/NAME` (the models
alone), run here when its binary is given (--cxx, or found in build/release/bench). The batch
calls Machine::inverse and ::forward, which add the work envelope, assembly mode and joint-limit
checks, and converts units: the ratio is what a pose costs from Python over the model's own cost.

The overhead per call is split into: an empty call of the binding (a property, no arrays), a
one-pose inverse and forward (argument conversion, the machine's copy, the result arrays and
status strings) and a jacobian. Last, the wall time of two threads each running the batch IK
against one thread running it once (1.0: perfect overlap, 2.0: none; on 2 cores). Takes about
20 s (plus bench_kinematics' few seconds).

usage: PYTHONPATH=build/release/python bench/python_kinematics.py [--cxx BENCH_KINEMATICS]"""

import argparse
import json
import os
import subprocess
import threading
import timeit

import numpy as np

import pkmkit

HERE = os.path.dirname(os.path.abspath(__file__))
MACHINES = os.path.join(HERE, "..", "examples", "machines")
# Poses within these distances of home: mm for x y z, deg for a b c.
SPREAD = {"hektor.toml": 20.0, "triaglide.toml": 20.0, "hexapod-bit.toml": [50, 50, 50, 5, 5, 5]}
IK_POSES = 1_000_000
FK_POSES = 200_000
CALLS = 20_000


def best(function, number=1):
    return min(timeit.repeat(function, number=number, repeat=3)) / number


def cxx_figures(binary):
    """{'inverse/hektor': ns, ...} from bench_kinematics' JSON, for the machines above."""
    names = "|".join(name.removesuffix(".toml") for name in SPREAD)
    result = subprocess.run([binary, f"--benchmark_filter=^(inverse|forward_from_home)/({names})$",
                             "--benchmark_format=json"], capture_output=True, text=True,
                            check=True)
    return {b["name"]: b["real_time"] for b in json.loads(result.stdout)["benchmarks"]
            if b["time_unit"] == "ns"}


def per_call_us(m):
    """µs per call: an empty one (a property), one-pose inverse and forward, a jacobian."""
    one = m.home[None, :].copy()
    joints = m.inverse(one)[0]
    return [best(f, CALLS) * 1e6 for f in (lambda: m.dof, lambda: m.inverse(one),
                                           lambda: m.forward(joints), lambda: m.jacobian(m.home))]


def two_threads_over_one(m, poses):
    """Wall time of two threads each running inverse(poses), over one thread running it once."""
    def both():
        threads = [threading.Thread(target=m.inverse, args=(poses,)) for _ in range(2)]
        for thread in threads:
            thread.start()
        for thread in threads:
            thread.join()
    return best(both) / best(lambda: m.inverse(poses))


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    default = os.path.join(HERE, "..", "build", "release", "bench", "bench_kinematics")
    parser.add_argument("--cxx", default=default if os.access(default, os.X_OK) else None,
                        help="the bench_kinematics binary (default: build/release/bench's)")
    cxx = cxx_figures(parser.parse_args().cxx) if parser.parse_args().cxx else {}
    print(f"{'machine':>18} {'IK ns/pose':>10} {'C++ IK':>7} {'ratio':>6} {'FK ns/pose':>10} "
          f"{'C++ FK':>7} {'ratio':>6} | per call, us: {'empty':>5} {'ik(1)':>6} {'fk(1)':>6} "
          f"{'jac':>6}")
    for name, spread in SPREAD.items():
        m = pkmkit.Machine.load(os.path.join(MACHINES, name))
        rng = np.random.default_rng(1)
        poses = m.home + rng.uniform(-1, 1, (IK_POSES, m.dof)) * np.asarray(spread)
        joints, status = m.inverse(poses)
        assert np.all(status == "ok"), name
        ik = best(lambda: m.inverse(poses)) / IK_POSES * 1e9
        path = joints[:FK_POSES]  # random order: each seed is far from its answer
        fk = best(lambda: m.forward(path)) / FK_POSES * 1e9
        key = name.removesuffix(".toml")
        cxx_ik, cxx_fk = cxx.get(f"inverse/{key}"), cxx.get(f"forward_from_home/{key}")
        shown = [f"{v:7.1f} {mine / v:6.2f}" if v else f"{'-':>7} {'-':>6}"
                 for v, mine in ((cxx_ik, ik), (cxx_fk, fk))]
        calls = " ".join(f"{c:6.2f}" for c in per_call_us(m))
        print(f"{name:>18} {ik:10.1f} {shown[0]} {fk:10.1f} {shown[1]} |              {calls}")
    m = pkmkit.Machine.load(os.path.join(MACHINES, "hexapod-bit.toml"))
    poses = m.home + np.random.default_rng(2).uniform(-1, 1, (IK_POSES // 2, 6)) * 4.0
    print(f"hexapod-bit IK, two threads at once: {two_threads_over_one(m, poses):.2f} x the wall "
          f"time of one (2.0: no overlap)")


if __name__ == "__main__":
    main()
