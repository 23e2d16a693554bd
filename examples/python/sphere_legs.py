"""The paper's sphere planned on the paper's hexapod: the six leg lengths over the job.

Plans examples/jobs/sphere.ngc (a 60 deg cap of a 100 mm sphere, the tool normal to the surface)
on examples/machines/hexapod-bit.toml with pkmkit.plan, as `pkm plan` does, and plots each leg's
length against time, with the joints' limits from the machine file.

    PYTHONPATH=build/release/python python3 examples/python/sphere_legs.py [OUT.png]
"""
import pathlib
import sys

import matplotlib

matplotlib.use("Agg")  # headless: write the PNG, open no window
import matplotlib.pyplot as plt  # noqa: E402

import pkmkit  # noqa: E402

ROOT = pathlib.Path(__file__).resolve().parents[2]


def main(out):
    m = pkmkit.Machine.load(str(ROOT / "examples/machines/hexapod-bit.toml"))
    samples, report = pkmkit.plan(m, str(ROOT / "examples/jobs/sphere.ngc"), period=0.002)
    figure, axis = plt.subplots(figsize=(10, 5), constrained_layout=True)
    for joint in m.joints:
        axis.plot(samples["t"], samples["j_" + joint.name], linewidth=1, label=joint.name)
    low, high = min(j.min for j in m.joints), max(j.max for j in m.joints)
    for limit in (low, high):
        axis.axhline(limit, color="grey", linestyle="--", linewidth=0.8)
    axis.set(xlabel="t (s)", ylabel=f"leg length ({m.joints[0].unit})",
             title=f"sphere.ngc on {m.name}: {report['duration_s']:.2f} s, "
                   f"{report['samples']} samples at {report['period_s'] * 1000:g} ms")
    axis.legend(ncol=6, loc="upper center")
    figure.savefig(out, dpi=80)
    ranges = ", ".join(f"{j['name']} {j['min']:.1f}..{j['max']:.1f}" for j in report["joints"])
    print(f"{out}: {len(samples)} samples; legs (mm) {ranges}")


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "sphere_legs.png")
