#!/usr/bin/python3
"""The screenshots of docs/html-views.md: the example pages of test_views.py, posed mid-job,
cropped to the page. usage: screenshots.py PKM SOURCE_DIR OUT_DIR IMAGES_DIR WORKSPACE_PAGE_EXE"""

import io
import os
import sys

from PIL import Image

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from browser import Browser  # noqa: E402
import test_views  # noqa: E402

# page name, image name, where the slider stands (fraction of the job), zoomed to the path
SHOTS = [("demo", "plan-hexapod", 0.42, False), ("demo", "plan-hexapod-path", 0.42, True),
         ("hektor", "plan-hektor", 0.3, False), ("triaglide", "plan-triaglide", 0.55, False),
         ("hektor-post", "post-hektor", 0.5, False),
         ("sphere-hexapod-verify", "verify-hexapod", 0.6, True),
         ("plotter", "plan-plotter", 0.5, True), ("hektor-failing", "verify-failing", 0.5, False),
         ("plotter-view", "view-plotter", 0.5, True),
         ("workspace-hektor", "workspace-hektor", 0.0, False),
         ("workspace-triaglide", "workspace-triaglide", 0.0, False)]


def shoot(browser, html, path, fraction, zoom):
    """The page with its slider at `fraction` of the job (zoomed to the path), cropped to the page."""
    browser.load(html)
    browser.script("var s = document.getElementById('slider');"
                   "s.value = String(Math.round(arguments[0] * 10000));"
                   "s.dispatchEvent(new Event('input'));", fraction)
    if zoom:
        browser.script("document.getElementById('fit').click();")
    browser.script("return new Promise(function (r) { requestAnimationFrame(function () {"
                   " requestAnimationFrame(function () { r(); }); }); });")
    bottom = browser.script(
        "return Math.ceil(document.querySelector('footer').getBoundingClientRect().bottom)")
    shot = Image.open(io.BytesIO(browser.driver.get_screenshot_as_png())).convert("RGB")
    shot = shot.crop((0, 0, shot.width, min(shot.height, bottom)))
    shot.save(path, optimize=True)
    print(path, shot.size)


def main():
    pkm, source, out, images, workspace_page = sys.argv[1:6]
    os.makedirs(out, exist_ok=True)
    with open(os.path.join(out, "triaglide-square.ngc"), "w") as job:
        job.write(test_views.TRIAGLIDE_JOB)
    with open(os.path.join(out, "plotter-square.ngc"), "w") as job:
        job.write(test_views.PLOTTER_JOB)
    made = {name: html for name, _, html, _ in test_views.pages(pkm, source, out, workspace_page)}
    browser = Browser(width=1400, height=1100)
    try:
        for page, image, fraction, zoom in SHOTS:
            shoot(browser, made[page], os.path.join(images, image + ".png"), fraction, zoom)
    finally:
        browser.close()


if __name__ == "__main__":
    main()
