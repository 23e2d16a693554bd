#!/usr/bin/env python3
"""Writes examples/jobs/sphere.ngc and hyperboloid.ngc: the test parts of the interpolation paper.

Sphere of radius 100 mm, centre 980 mm above the base, machined over a cap of 60 deg from its
pole, the tool tip on the surface and the tool axis along the surface normal. The path follows
circles of latitude (G3 arcs of 30 deg in XY, the paper's circular interpolation) from 60 deg to
5 deg, stepping along a meridian between them. The tool is tilted about a horizontal axis (the
paper's choice gamma = -alpha: no spin of the platform about its own axis); each arc end carries
that attitude as A B C (deg, R = Rz(C) Ry(B) Rx(A)).

The hyperboloid of one sheet (waist radius 100 mm, rulings at 20 deg to its axis, 200 mm tool)
lies with its axis along X, 780 mm above the base, and is machined over the band of +-10 deg
about its top by straight lines along its rulings (the paper's linear interpolation), each split
into ten G1 moves that carry the surface normal as the tool attitude.
Standard library only; rerun it after changing a parameter: python3 tools/make-paper-jobs.py
"""
import math
import pathlib

RADIUS = 100.0          # mm
CENTRE_Z = 980.0        # mm
CAP_DEG = 60.0          # polar angle of the cap's rim
LATITUDE_STEP_DEG = 5.0
ARC_DEG = 30.0
FEED = 1000.0           # mm/min


def tilt_to(normal):
    """A B C (deg) of the rotation tilting +Z onto `normal` about a horizontal axis."""
    nx, ny, nz = normal
    polar = math.acos(max(-1.0, min(1.0, nz)))
    azimuth = math.atan2(ny, nx)
    return tilt_abc(polar, azimuth)


def tilt_abc(polar, azimuth):
    """A B C (deg) of the rotation tilting +Z onto the normal by `polar` about the horizontal
    axis perpendicular to the azimuth."""
    kx, ky = -math.sin(azimuth), math.cos(azimuth)
    c, s = math.cos(polar), math.sin(polar)
    # Rodrigues with k = (kx, ky, 0).
    r = [[c + (1 - c) * kx * kx, (1 - c) * kx * ky, s * ky],
         [(1 - c) * kx * ky, c + (1 - c) * ky * ky, -s * kx],
         [-s * ky, s * kx, c]]
    b = -math.asin(max(-1.0, min(1.0, r[2][0])))
    a = math.atan2(r[2][1], r[2][2])
    cc = math.atan2(r[1][0], r[0][0])
    return tuple(math.degrees(v) for v in (a, b, cc))


def point(polar_deg, azimuth_deg):
    polar, azimuth = math.radians(polar_deg), math.radians(azimuth_deg)
    x = RADIUS * math.sin(polar) * math.cos(azimuth)
    y = RADIUS * math.sin(polar) * math.sin(azimuth)
    z = CENTRE_Z + RADIUS * math.cos(polar)
    return (x, y, z) + tilt_abc(polar, azimuth)


previous_angles = [0.0, 0.0, 0.0]


def words(p):
    """The point's words, its angles unwrapped to within 180 deg of the previous point's, so
    that interpolating them linearly turns the short way."""
    angles = list(p[3:])
    for i in range(3):
        while angles[i] - previous_angles[i] > 180.0:
            angles[i] -= 360.0
        while angles[i] - previous_angles[i] < -180.0:
            angles[i] += 360.0
        previous_angles[i] = angles[i]
    return "X%.4f Y%.4f Z%.4f A%.4f B%.4f C%.4f" % (tuple(p[:3]) + tuple(angles))


def main():
    lines = [
        "%",
        "(Sphere test part of the Stewart-platform interpolation paper, made by)",
        "(tools/make-paper-jobs.py: radius %.0f mm, centre at Z%.0f, a %.0f deg cap,)" % (RADIUS, CENTRE_Z, CAP_DEG),
        "(tool axis normal to the surface, circles of latitude as G3 arcs of %.0f deg)" % ARC_DEG,
        "G21 G90 G17 G94 G64",
    ]
    polar = CAP_DEG
    lines.append("G0 " + words(point(polar, 0.0)))
    lines.append("F%.0f" % FEED)
    while polar >= LATITUDE_STEP_DEG - 1e-9:
        circle_radius = RADIUS * math.sin(math.radians(polar))
        azimuth = 0.0
        while azimuth < 360.0 - 1e-9:
            azimuth += ARC_DEG
            end = point(polar, azimuth % 360.0)
            lines.append("G3 %s I%.4f J%.4f" % (words(end),
                                                 -circle_radius * math.cos(math.radians(azimuth - ARC_DEG)),
                                                 -circle_radius * math.sin(math.radians(azimuth - ARC_DEG))))
        polar -= LATITUDE_STEP_DEG
        if polar >= LATITUDE_STEP_DEG - 1e-9:
            lines.append("G1 " + words(point(polar, 0.0)))
    lines.append("G0 Z%.4f A0 B0 C0" % (CENTRE_Z + RADIUS + 20.0))
    lines.append("M2")
    lines.append("%")
    out = pathlib.Path(__file__).resolve().parent.parent / "examples" / "jobs" / "sphere.ngc"
    out.write_text("\n".join(lines) + "\n")
    print("wrote", out, len(lines), "lines")


HYPERBOLOID_RADIUS = 100.0   # mm, waist
HYPERBOLOID_AXIS_Z = 780.0   # mm
RULING_DEG = 20.0            # angle of the rulings to the axis
BAND_DEG = 10.0              # machined band: +-10 deg about the top
RULING_HALF_LENGTH = 60.0    # mm either side of the waist
RULING_STEPS = 10
RULINGS = 21


def hyperboloid_point(theta, t):
    """Point and outward normal at waist angle theta (0 = top) and ruling parameter t (mm)."""
    beta = math.radians(RULING_DEG)
    a = HYPERBOLOID_RADIUS
    waist = (0.0, a * math.sin(theta), a * math.cos(theta))
    tangent = (0.0, math.cos(theta), -math.sin(theta))
    d = (math.cos(beta), math.sin(beta) * tangent[1], math.sin(beta) * tangent[2])
    p = tuple(waist[i] + t * d[i] for i in range(3))
    # dP/dtheta and dP/dt; the normal is their cross product, turned away from the axis.
    dw = (0.0, a * math.cos(theta), -a * math.sin(theta))
    dd = (0.0, -math.sin(beta) * math.sin(theta), -math.sin(beta) * math.cos(theta))
    u = tuple(dw[i] + t * dd[i] for i in range(3))
    n = (u[1] * d[2] - u[2] * d[1], u[2] * d[0] - u[0] * d[2], u[0] * d[1] - u[1] * d[0])
    length = math.sqrt(sum(c * c for c in n))
    n = tuple(c / length for c in n)
    if n[1] * p[1] + n[2] * p[2] < 0:
        n = tuple(-c for c in n)
    return (p[0], p[1], p[2] + HYPERBOLOID_AXIS_Z), n


def hyperboloid():
    previous_angles[:] = [0.0, 0.0, 0.0]
    lines = [
        "%",
        "(Hyperboloid test part of the Stewart-platform interpolation paper, made by)",
        "(tools/make-paper-jobs.py: one sheet, waist radius %.0f mm, rulings at %.0f deg,)" % (HYPERBOLOID_RADIUS, RULING_DEG),
        "(axis along X at Z%.0f, the band of +-%.0f deg about its top, along its rulings,)" % (HYPERBOLOID_AXIS_Z, BAND_DEG),
        "(tool axis normal to the surface; for the 200 mm tool of hexapod-bit-200.toml)",
        "G21 G90 G17 G94 G64",
    ]
    for k in range(RULINGS):
        theta = math.radians(-BAND_DEG + 2 * BAND_DEG * k / (RULINGS - 1))
        direction = 1 if k % 2 == 0 else -1  # back and forth
        ts = [direction * (-RULING_HALF_LENGTH + 2 * RULING_HALF_LENGTH * i / RULING_STEPS)
              for i in range(RULING_STEPS + 1)]
        for i, t in enumerate(ts):
            p, n = hyperboloid_point(theta, t)
            word = words(p + tilt_to(n))
            if k == 0 and i == 0:
                lines.append("G0 " + word)
                lines.append("F800")
            else:
                lines.append("G1 " + word)
    lines.append("G0 Z%.4f A0 B0 C0" % (HYPERBOLOID_AXIS_Z + HYPERBOLOID_RADIUS + 20.0))
    lines.append("M2")
    lines.append("%")
    out = pathlib.Path(__file__).resolve().parent.parent / "examples" / "jobs" / "hyperboloid.ngc"
    out.write_text("\n".join(lines) + "\n")
    print("wrote", out, len(lines), "lines")


if __name__ == "__main__":
    main()
    hyperboloid()
