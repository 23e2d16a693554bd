"""The wall plotter's joint speed per unit pen speed over the sheet, from its Jacobian.

Loads examples/machines/wall-plotter.toml (two cords from motors 1.5 m apart), and at every
point of a 10 mm grid the machine reaches computes the Jacobian J = d cords / d pen (mm per mm).
Plotted, for the worst direction of the pen at each point:
  left:  the cords' speed needed per unit pen speed, the largest singular value of J (1 where the
         cords cross at right angles, up to sqrt(2) where they run side by side);
  right: the pen speed per unit cord speed, 1 / the smallest singular value of J: how far the pen
         moves for a millimetre of cord, large near the motor line, where the cords pull sideways.

    PYTHONPATH=build/release/python python3 examples/python/wall_plotter_speed.py [OUT.png]
"""
import pathlib
import sys

import matplotlib

matplotlib.use("Agg")  # headless: write the PNG, open no window
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import pkmkit  # noqa: E402

ROOT = pathlib.Path(__file__).resolve().parents[2]


def singular_values_over(machine, xs, ys):
    """(largest, smallest) singular value of the Jacobian at every grid point (NaN outside)."""
    grid = np.array([[x, y] for y in ys for x in xs])
    _, status = machine.inverse(grid)
    largest = np.full(len(grid), np.nan)
    smallest = np.full(len(grid), np.nan)
    for i in np.flatnonzero(status == "ok"):
        values = np.linalg.svd(machine.jacobian(grid[i]), compute_uv=False)
        largest[i], smallest[i] = values[0], values[-1]
    shape = (len(ys), len(xs))
    return largest.reshape(shape), smallest.reshape(shape)


def main(out):
    m = pkmkit.Machine.load(str(ROOT / "examples/machines/wall-plotter.toml"))
    xs = np.arange(0.0, 1500.0 + 1e-9, 10.0)
    ys = np.arange(-2100.0, 0.0 + 1e-9, 10.0)
    largest, smallest = singular_values_over(m, xs, ys)
    anchors = np.array([[m.parameters["anchor_left_x"], m.parameters["anchor_left_y"]],
                        [m.parameters["anchor_right_x"], m.parameters["anchor_right_y"]]])
    figure, axes = plt.subplots(1, 2, figsize=(12, 6), constrained_layout=True)
    panels = [(largest, "cord speed per unit pen speed (worst direction)", None),
              (1.0 / smallest, "pen speed per unit cord speed (worst direction)",
               matplotlib.colors.LogNorm(vmin=1.0, vmax=10.0))]
    for axis, (values, title, norm) in zip(axes, panels):
        image = axis.pcolormesh(xs, ys, values, shading="nearest", norm=norm, cmap="viridis")
        axis.plot(anchors[:, 0], anchors[:, 1], "rv", label="motors")
        axis.plot(*m.home, "w+", markersize=12, label="home")
        axis.set(title=title, xlabel="x (mm)", ylabel="y (mm)", aspect="equal")
        axis.legend(loc="lower right")
        figure.colorbar(image, ax=axis, shrink=0.8)
    figure.suptitle(f"{m.name}: what the Jacobian asks of the motors over the reachable sheet")
    figure.savefig(out, dpi=80)
    reach = np.isfinite(largest)
    print(f"{out}: {reach.sum()} of {reach.size} grid points reachable; cord speed per pen speed "
          f"{np.nanmin(largest):.3f} .. {np.nanmax(largest):.3f}; pen per cord up to "
          f"{np.nanmax(1.0 / smallest):.1f}")


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "wall_plotter_speed.png")
