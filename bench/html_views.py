#!/usr/bin/python3
"""HTML size and load time of a plan's page as the samples grow to a million and beyond: the
paper's sphere planned on its hexapod at shorter and shorter periods, each page loaded in headless
Chromium (tests/browser). Load: from navigation to the view's first full drawing (as the page
measures it, and as the driver waits for it, which adds the browser's own round trips);
respond: from a slider move to the next frame drawn; each the best of three.

usage: bench/html_views.py [PKM] (default build/release/apps/pkm/pkm)"""

import os
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "tests", "browser"))
from browser import Browser  # noqa: E402

SOURCE = os.path.join(HERE, "..")
PERIODS = [0.001, 0.00025, 0.0001]  # 250 000, 1 000 000 and 2 500 000 samples


def main():
    pkm = sys.argv[1] if len(sys.argv) > 1 else os.path.join(SOURCE, "build/release/apps/pkm/pkm")
    job = os.path.join(SOURCE, "examples/jobs/sphere.ngc")
    out = tempfile.mkdtemp(prefix="pkm-html-bench-")
    browser = Browser()
    print(f"{'samples':>10} {'plan+page s':>12} {'HTML kB':>9} {'load ms':>8} {'wall ms':>8} "
          f"{'respond ms':>11}")
    try:
        for period in PERIODS:
            html = os.path.join(out, f"sphere-{period}.html")
            started = time.time()
            text = subprocess.run([pkm, "plan", job, "--period", str(period), "--html", html,
                                   "--max-samples", "100000000"],
                                  check=True, capture_output=True, text=True).stdout
            planned = time.time() - started
            samples = int(text.split(": ")[1].split(" ")[0])
            loads, walls, responds = [], [], []
            for _ in range(3):
                started = time.time()
                browser.load(html)
                walls.append(1000 * (time.time() - started))
                loads.append(browser.script("return window.pkmView.readyAt"))
                responds.append(browser.script(
                    "var t0 = performance.now(); window.pkmView.setT(120);"
                    "return new Promise(function (r) { requestAnimationFrame(function () {"
                    " requestAnimationFrame(function () { r(performance.now() - t0); }); }); });"))
            print(f"{samples:>10} {planned:>12.2f} {os.path.getsize(html) / 1e3:>9.0f} "
                  f"{min(loads):>8.0f} {min(walls):>8.0f} {min(responds):>11.1f}")
    finally:
        browser.close()


if __name__ == "__main__":
    main()
