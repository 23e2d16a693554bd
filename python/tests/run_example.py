"""Runs one example of examples/python/ (ctest, label python) and checks its picture.

    run_example.py EXAMPLE.py OUT.png

The example must exit 0 and write OUT.png; the picture must not be blank: more than a few
distinct colours, and no single colour over 97 % of it (an empty axes frame is one colour and a
few greys).
"""
import pathlib
import subprocess
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.image  # noqa: E402
import numpy as np  # noqa: E402


def main(example, out):
    out = pathlib.Path(out)
    out.unlink(missing_ok=True)
    subprocess.run([sys.executable, example, str(out)], check=True)
    if not out.exists():
        sys.exit(f"{example} wrote no {out}")
    pixels = matplotlib.image.imread(str(out))
    rgb = (pixels[..., :3] * 255).astype(np.uint8).reshape(-1, 3)
    colours, counts = np.unique(rgb, axis=0, return_counts=True)
    share = counts.max() / counts.sum()
    print(f"{out}: {pixels.shape[1]}x{pixels.shape[0]}, {len(colours)} colours, the commonest "
          f"{share:.1%}")
    if len(colours) < 20 or share > 0.97:
        sys.exit(f"{out} looks blank: {len(colours)} colours, one of them {share:.1%}")


if __name__ == "__main__":
    main(*sys.argv[1:])
