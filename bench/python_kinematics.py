#!/usr/bin/python3
"""Batch kinematics from Python (the pkmkit module, docs/python.md): ns per pose for IK and FK
over a million poses, and the binding's overhead per call (one pose), for a few example machines;
each the best of three (timeit). Compare with bench_kinematics (the C++ models alone: `inverse/`
and `forward_from_home/`): the batch calls Machine::inverse and ::forward, which add the work
envelope, assembly mode and joint-limit checks, and converts units. Takes about 10 s.

usage: PYTHONPATH=build/release/python bench/python_kinematics.py"""

import os
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


def main():
    print(f"{'machine':>18} {'IK ns/pose':>11} {'FK ns/pose':>11} {'call us':>8}")
    for name, spread in SPREAD.items():
        m = pkmkit.Machine.load(os.path.join(MACHINES, name))
        rng = np.random.default_rng(1)
        poses = m.home + rng.uniform(-1, 1, (IK_POSES, m.dof)) * np.asarray(spread)
        joints, status = m.inverse(poses)
        assert np.all(status == "ok"), name
        ik = best(lambda: m.inverse(poses)) / IK_POSES
        path = joints[:FK_POSES]  # random order: each seed is far from its answer
        fk = best(lambda: m.forward(path)) / FK_POSES
        one = poses[:1].copy()
        call = best(lambda: m.inverse(one), CALLS)
        print(f"{name:>18} {ik * 1e9:11.1f} {fk * 1e9:11.1f} {call * 1e6:8.2f}")


if __name__ == "__main__":
    main()
