#!/usr/bin/env python3
"""Joint readings of a hidden cable robot at poses nobody measured, for `pkm calibrate readings`.

Reads the anchors of a machine file (type = "cable_robot", every attach point at the tool, no
cable offsets), moves each anchor by --shift (mm, "dx,dy,dz" per cable, separated by blanks), and writes a CSV of the
cable lengths of that hidden machine at --samples random positions inside the anchors' tetrahedron
(barycentric coordinates each at least --margin, so the lines hold the effector), counted from
home (the origin) as a Hangprinter's encoders count from power-on (--absolute: the lengths
themselves), with Gaussian noise of --noise mm on every reading. An independent
implementation of the cable lengths: |anchor - position|.

--motor-degrees writes what Hangprinter's encoders read instead: each motor's position in degrees
from the origin, from the (noisy) line length through the spool build-up as Hangprinter's
auto-calibration script models it (k2 = -U O Q, k0 = 2 (H / L) U 360 / (2 pi k2), degrees =
k0 (sqrt(r^2 + k2 p) - r) for p mm of line paid out since the origin), with the machine file's
spool_radius, spool_buildup, mechanical_advantage, lines_per_spool, motor_gear_teeth and
spool_gear_teeth.

  tools/make-cable-readings.py examples/machines/hangprinter-v4.toml \\
      --shift '0,-25,18 30,-22,15 -28,27,-20 0,0,35' > readings.csv
"""
import argparse
import math
import random
import sys
import tomllib


def barycentric(point, corners):
    """Barycentric coordinates of `point` in the tetrahedron `corners` (4 points)."""
    a, b, c, d = corners
    columns = [[b[k] - a[k], c[k] - a[k], d[k] - a[k]] for k in range(3)]
    rhs = [point[k] - a[k] for k in range(3)]

    def det(m):
        return (m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
                - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
                + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]))

    whole = det(columns)
    weights = []
    for col in range(3):
        replaced = [row[:] for row in columns]
        for k in range(3):
            replaced[k][col] = rhs[k]
        weights.append(det(replaced) / whole)
    return [1.0 - sum(weights)] + weights


def spool_key(machine, cable, key, default):
    """A spool key of the cable, else of [kinematics], else `default`."""
    return cable.get(key, machine["kinematics"].get(key, default))


def motor_degrees(machine, cable, paid_out_mm):
    """Hangprinter's motor position (deg from the origin) for `paid_out_mm` of line since then."""
    radius = spool_key(machine, cable, "spool_radius", None)
    if radius is None:
        sys.exit("--motor-degrees needs every cable's spool_radius")
    advantage = spool_key(machine, cable, "mechanical_advantage", 1)
    k2 = -advantage * spool_key(machine, cable, "lines_per_spool", 1) * \
        machine["kinematics"].get("spool_buildup", 0.0)
    gearing = spool_key(machine, cable, "spool_gear_teeth", 1) / \
        spool_key(machine, cable, "motor_gear_teeth", 1)
    degrees_times_radius = gearing * advantage * 360.0 / (2.0 * math.pi)
    if k2 == 0.0:
        return degrees_times_radius / radius * paid_out_mm
    k0 = 2.0 * degrees_times_radius / k2
    return k0 * (math.sqrt(radius * radius + k2 * paid_out_mm) - radius)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("machine")
    parser.add_argument("--shift", default="", help="'dx,dy,dz dx,dy,dz ..' per cable, mm")
    parser.add_argument("--samples", type=int, default=30)
    parser.add_argument("--noise", type=float, default=0.05, help="mm")
    parser.add_argument("--margin", type=float, default=0.12)
    parser.add_argument("--box", type=float, nargs=6, default=[-600, -600, 0, 600, 600, 1200],
                        help="x y z min, x y z max, mm")
    parser.add_argument("--seed", type=int, default=31)
    parser.add_argument("--absolute", action="store_true",
                        help="write the lengths themselves, not counted from home")
    parser.add_argument("--motor-degrees", action="store_true",
                        help="write motor positions (deg from the origin) through the spools")
    args = parser.parse_args()
    with open(args.machine, "rb") as file:
        machine = tomllib.load(file)
    cables = machine["kinematics"]["cables"]
    names = [joint["name"] for joint in machine["joints"]]
    if len(cables) != 4 or len(names) != 4:
        sys.exit("this script reads four cables in space")
    if args.motor_degrees and args.absolute:
        sys.exit("motor degrees count from the origin: no --absolute")
    anchors = [list(cable["anchor"]) for cable in cables]
    for i, text in enumerate(args.shift.split()):
        for k, value in enumerate(text.split(",")):
            anchors[i][k] += float(value)
    home = [0.0, 0.0, 0.0]
    zero = [0.0 if args.absolute else math.dist(anchor, home) for anchor in anchors]
    rng = random.Random(args.seed)
    low, high = args.box[:3], args.box[3:]
    print(",".join("j_" + name for name in names))
    written = 0
    while written < args.samples:
        point = [rng.uniform(low[k], high[k]) for k in range(3)]
        if min(barycentric(point, anchors)) < args.margin:
            continue
        readings = [math.dist(anchor, point) - zero[i] + rng.gauss(0.0, args.noise)
                    for i, anchor in enumerate(anchors)]
        if args.motor_degrees:
            readings = [motor_degrees(machine, cables[i], value)
                        for i, value in enumerate(readings)]
        print(",".join(f"{value:.4f}" for value in readings))
        written += 1


if __name__ == "__main__":
    main()
