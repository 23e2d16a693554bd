#!/usr/bin/env python3
"""The HTML views in a real headless Chromium: every page of the example jobs (plan, post, verify
on a hexapod, a cable plotter, a glide and a Hangprinter) loads with no console error and no network request,
its drawing and charts are not blank (pixel statistics of screenshots), the slider moves the drawn
machine, every number of its summary equals the JSON report's, and a machine hung on cables shows
each cable's tension at the drawn moment (home's at the start).

usage: test_views.py PKM SOURCE_DIR OUT_DIR [--screenshots DIR] [--workspace-page EXE]"""

import argparse
import collections
import json
import os
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
try:
    from browser import Browser, changed_pixels, distinct_colours, non_background_fraction  # noqa
except ImportError as missing:
    print(f"skipped: {missing} (scripts/setup test installs python3-selenium and python3-pil)")
    sys.exit(77)
if not (os.path.exists("/usr/bin/chromium") and os.path.exists("/usr/bin/chromedriver")):
    print("skipped: no /usr/bin/chromium or /usr/bin/chromedriver (scripts/setup test)")
    sys.exit(77)

failures = []


def check(condition, what):
    if not condition:
        failures.append(what)
        print("FAIL:", what)


def run(*command):
    result = subprocess.run(command, capture_output=True, text=True)
    if result.returncode != 0:
        raise SystemExit(f"{' '.join(command)} failed ({result.returncode}):\n{result.stderr}")
    return result.stdout


def pages(pkm, source, out, workspace_page):
    """Writes each page with its JSON report; returns (name, kind, html, report) tuples."""
    machines = os.path.join(source, "examples", "machines")
    jobs = os.path.join(source, "examples", "jobs")
    data = os.path.join(source, "tests", "data")
    made = []

    def plan(name, machine, job, *extra):
        html, report = os.path.join(out, name + ".html"), os.path.join(out, name + ".json")
        run(pkm, "plan", "-m", os.path.join(machines, machine), job, "--report", report,
            "--html", html, *extra)
        made.append((name, "plan", html, report))

    def post_and_verify(name, machine, job, tolerance, *extra):
        program = os.path.join(out, name + "-joints.ngc")
        html, report = os.path.join(out, name + "-post.html"), os.path.join(out, name + "-post.json")
        run(pkm, "post", "-m", os.path.join(machines, machine), job, "-o", program,
            "--tolerance", tolerance, "--report", report, "--html", html, *extra)
        made.append((name + "-post", "post", html, report))
        html, report = os.path.join(out, name + "-verify.html"), os.path.join(out, name + "-verify.json")
        run(pkm, "verify", "-m", os.path.join(machines, machine), program, "--against", job,
            "--report", report, "--html", html, *extra)
        made.append((name + "-verify", "verify", html, report))

    html, report = os.path.join(out, "demo.html"), os.path.join(out, "demo.json")
    run(pkm, "demo", "--report", report, "--html", html)
    made.append(("demo", "plan", html, report))
    plan("sphere-hexapod", "hexapod-bit.toml", os.path.join(jobs, "sphere.ngc"))
    plan("hyperboloid-hexapod", "hexapod-bit-200.toml", os.path.join(jobs, "hyperboloid.ngc"))
    plan("hektor", "hektor.toml", os.path.join(data, "hektor-job.ngc"))
    plan("triaglide", "triaglide.toml", os.path.join(out, "triaglide-square.ngc"))
    plan("plotter", "pen-plotter.toml", os.path.join(out, "plotter-square.ngc"))
    plan("hangprinter", "hangprinter-v4.toml", os.path.join(out, "hangprinter-square.ngc"))
    post_and_verify("sphere-hexapod", "hexapod-bit.toml", os.path.join(jobs, "sphere.ngc"), "0.01")
    post_and_verify("hektor", "hektor.toml", os.path.join(data, "hektor-job.ngc"), "0.05")
    # pkm view of joint programs alone: the pen plotter's square (pen up and down), Hektor's job.
    for name, machine, program in (
            ("plotter", "pen-plotter.toml", os.path.join(out, "plotter-square.ngc")),
            ("hektor", "hektor.toml", None)):
        joints = os.path.join(out, name + "-joints.ngc")
        if program:
            run(pkm, "post", "-m", os.path.join(machines, machine), program, "-o", joints)
        html, report = os.path.join(out, name + "-view.html"), os.path.join(out, name + "-view.json")
        run(pkm, "view", "-m", os.path.join(machines, machine), joints, "--report", report,
            "--html", html)
        made.append((name + "-view", "view", html, report))
    # The same joint program held against the job moved 30 mm: a failing verification.
    html, report = os.path.join(out, "hektor-failing.html"), os.path.join(out, "hektor-failing.json")
    result = subprocess.run([pkm, "verify", "-m", os.path.join(machines, "hektor.toml"),
                             os.path.join(out, "hektor-joints.ngc"), "--against",
                             os.path.join(data, "hektor-job.ngc"), "--origin", "30", "0",
                             "--report", report, "--html", html], capture_output=True, text=True)
    if result.returncode != 1:
        raise SystemExit(f"the moved verification should fail:\n{result.stdout}{result.stderr}")
    made.append(("hektor-failing", "verify", html, report))
    # Real `pkm workspace --json --html` outputs: the paper's hexapod with 45 deg joints and 40 mm
    # legs (3-D), and Hektor (planar).
    with open(os.path.join(machines, "hexapod-bit.toml")) as file:
        limited = file.read().replace("tool_length = 30.0\n", "tool_length = 30.0\n"
                                      "max_joint_angle = 45.0\nleg_diameter = 40.0\n")
    with open(os.path.join(out, "hexapod-limited.toml"), "w") as file:
        file.write(limited)
    for name, machine, resolution in (
            ("workspace-hexapod-limited", os.path.join(out, "hexapod-limited.toml"), "16"),
            ("workspace-hektor-real", os.path.join(machines, "hektor.toml"), "1")):
        html, report = os.path.join(out, name + ".html"), os.path.join(out, name + ".json")
        with open(report, "w") as file:
            file.write(run(pkm, "workspace", "-m", machine, "--resolution", resolution, "--json",
                           "--html", html))
        made.append((name, "workspace", html, report))
    if workspace_page:
        html, report = os.path.join(out, "workspace-hektor.html"), os.path.join(
            data, "workspace-hektor.json")
        run(workspace_page, report, html, os.path.join(machines, "hektor.toml"))
        made.append(("workspace-hektor", "workspace", html, report))
        html, report = os.path.join(out, "workspace-triaglide.html"), os.path.join(
            data, "workspace-triaglide.json")
        run(workspace_page, report, html, os.path.join(machines, "triaglide.toml"))
        made.append(("workspace-triaglide", "workspace", html, report))
    return made


def expected_numbers(kind, report):
    """The summary's keys and the values the JSON report gives them."""
    if kind == "plan":
        numbers = {key: report[key] for key in ("duration_s", "path_length_mm", "samples")}
        numbers["feed_limited_by_joints"] = len(report["feed_limited_by_joints"])
        numbers["acceleration_limited_by_tensions"] = len(report["acceleration_limited_by_tensions"])
        numbers["warnings"] = len(report["warnings"])
        uses = [max(j["peak_velocity"] / j["max_velocity"],
                    j["peak_acceleration"] / j["max_acceleration"]) for j in report["joints"]]
        worst = max(range(len(uses)), key=lambda i: uses[i])
        numbers["worst_joint"] = report["joints"][worst]["name"]
        numbers["worst_joint_use"] = 100 * uses[worst]
        if report["pen_changes"]:
            numbers["pen_changes"] = report["pen_changes"]
        return numbers
    if kind == "workspace":
        size = report["area_mm2" if report["planar"] else "volume_mm3"]
        numbers = {"inside": size["inside"], "boundary": size["boundary"],  # area or volume
                   "resolution_mm": report["resolution_mm"],
                   "cylinder_radius": report["largest_cylinder_mm"]["radius"]}
        for status, cells in report["limited_by"].items():
            numbers["limited_by." + status] = cells
        return numbers
    if kind == "view":
        numbers = {key: report[key] for key in ("blocks", "drawn_mm", "travel_mm", "rapid_mm")}
        if report["pen_channel"]:
            numbers["pen_downs"] = report["pen_downs"]
        for joint in report["joints"]:
            numbers["margin_" + joint["name"]] = min(joint["margin_low"], joint["margin_high"])
        numbers["position_violations"] = report["violations"]["position"]["count"]
        return numbers
    if kind == "post":
        numbers = {key: report[key] for key in
                   ("blocks", "moves", "max_deviation_mm", "max_deviation_line", "tolerance_mm")}
        numbers["warnings"] = len(report["warnings"])
        return numbers
    numbers = {key: report[key] for key in ("blocks", "max_deviation_mm", "rms_deviation_mm",
                                            "tolerance_mm", "max_deviation_joint_line")}
    numbers["traced_mm"] = report["coverage"]["traced_mm"]
    numbers["job_length_mm"] = report["coverage"]["job_length_mm"]
    for kind_ in ("deviation", "position", "velocity", "pen"):
        numbers[kind_ + "_violations"] = report["violations"][kind_]["count"]
    numbers["passed"] = "yes" if report["passed"] else "no"
    return numbers


def equal(shown, expected):
    if isinstance(expected, str):
        return shown == expected
    value = float(shown)
    return abs(value - expected) <= 1e-8 * max(1.0, abs(expected))


def check_numbers(browser, name, kind, report):
    rows = browser.script(
        "return Array.from(document.querySelectorAll('#summary tr')).map(function (r) {"
        " return [r.dataset.key, r.querySelector('td.value').textContent]; });")
    shown = dict(rows)
    for key, expected in expected_numbers(kind, report).items():
        check(key in shown, f"{name}: the summary shows no {key}")
        if key in shown:
            check(equal(shown[key], expected),
                  f"{name}: {key} shown as {shown[key]}, the report says {expected}")


def check_page(browser, name, kind, html, report_path, screenshots):
    url = browser.load(html)
    errors = browser.console_errors()
    check(not errors, f"{name}: console errors {errors}")
    others = [u for u in browser.requests() if u != url]
    check(not others, f"{name}: network requests {others}")
    scene = browser.element_image("#scene")
    check(non_background_fraction(scene) > 0.01 and distinct_colours(scene) > 20,
          f"{name}: the drawing is blank ({non_background_fraction(scene):.4f} drawn, "
          f"{distinct_colours(scene)} colours)")
    for index in range(browser.script("return document.querySelectorAll('.chart canvas').length")):
        chart = browser.element_image(f".chart:nth-child({index + 1}) canvas")
        check(non_background_fraction(chart) > 0.02, f"{name}: chart {index + 1} is blank")
    with open(report_path) as file:
        check_numbers(browser, name, kind, json.load(file))
    if screenshots:
        browser.driver.save_screenshot(os.path.join(screenshots, name + ".png"))
    if kind == "verify":
        check_findings(browser, name, json.load(open(report_path)))
    if kind == "plan":
        check_speed_scale(browser, name, json.load(open(report_path)))
    check_tension_readout(browser, name)
    if kind == "workspace":
        report_maps = json.load(open(report_path))["maps"]
        maps = browser.script("return document.querySelectorAll('.map canvas').length")
        check(maps == len(report_maps), f"{name}: {maps} maps drawn")
        for index in range(min(maps, len(report_maps))):
            image = browser.element_image(f".map:nth-child({index + 1}) canvas")
            values = [v for v in report_maps[index]["values"] if v is not None]
            if max(values) - min(values) > 1e-9 * max(abs(v) for v in values):
                check(distinct_colours(image) > 5, f"{name}: map {index + 1} is blank")
                continue
            # Equal everywhere (joint speed per tool speed of legs and cables): one colour, said
            # so, and no rounding noise drawn as a range.
            text = browser.script(f"return document.querySelectorAll('.map')[{index}].textContent")
            counts = sorted(collections.Counter(image.getdata()).values(), reverse=True)
            two = sum(counts[:2]) / sum(counts)  # the map's colour and grey (unreachable)
            check("at every reachable point" in text and two > 0.97 and
                  non_background_fraction(image) > 0.2,
                  f"{name}: constant map {index + 1}: its two main colours cover {two:.3f}")
        return
    # The slider, clicked at its middle as a user would, poses the machine elsewhere (not at
    # its end: many jobs end where they started).
    slider = browser.driver.find_element("css selector", "#slider")
    browser.script("window.pkmView.setT(-1e300);")
    browser.script("return new Promise(function (r) { requestAnimationFrame(function () { r(); }); });")
    before = browser.element_image("#scene")
    frames = browser.script("return window.pkmView.frames")
    slider.click()
    browser.script("return new Promise(function (r) { requestAnimationFrame(function () { r(); }); });")
    after = browser.element_image("#scene")
    value = int(slider.get_attribute("value"))
    check(4000 < value < 6000, f"{name}: the slider's middle reads {value} of 10000")
    check(browser.script("return window.pkmView.frames") > frames, f"{name}: the slider drew nothing")
    check(changed_pixels(before, after) > 300,
          f"{name}: the slider did not move the drawn machine "
          f"({changed_pixels(before, after)} pixels changed)")


def check_findings(browser, name, report):
    """The verdict as a sentence; deviations listed worst first, the largest the report's."""
    verdict = browser.script("return document.getElementById('verdict').textContent")
    check(verdict.startswith("Passed" if report["passed"] else "Failed"),
          f"{name}: the verdict reads {verdict!r}")
    if report["violations"]["deviation"]["count"] == 0:
        return
    labels = browser.script("return window.pkmView.data.marks.map(function (m) { return m.label; })")
    worst = f"at joint-program line {report['max_deviation_joint_line']}, job line"
    check(labels and labels[0].startswith("deviation ") and worst in labels[0],
          f"{name}: the first finding is {labels[:1]}, not the worst ({worst})")


def check_tension_readout(browser, name):
    """A machine hung on cables: at the first drawn moment (home) the readout under the drawing
    names each cable with home's tension (the page's data, as pkm ik prints it), and its limits."""
    cables = browser.script("return window.pkmView.data.drawing.cables || null")
    if not cables:
        check(not browser.script("return document.getElementById('tension-readout').textContent"),
              f"{name}: a tension readout on a machine without cable tensions")
        return
    browser.script("window.pkmView.setT(window.pkmView.data.drawing.t[0]);")
    browser.script("return new Promise(function (r) { requestAnimationFrame(function () { r(); }); });")
    text = browser.script("return document.getElementById('tension-readout').textContent")
    expected = ("cable tensions at rest here: " +
                ", ".join(f"{n} {t:.2f} N" for n, t in zip(cables["names"], cables["home_N"])) +
                f" (limits {cables['limits']}); over the ")
    check(text.startswith(expected), f"{name}: the tension readout reads {text!r}, not {expected!r}")
    box = browser.script(
        "return document.getElementById('tension-readout').getBoundingClientRect().toJSON()")
    check(box["height"] > 0, f"{name}: the tension readout is not shown")


def check_speed_scale(browser, name, report):
    """The speed's colour scale ends at most at the machine's fastest feed (a pen plotter's pen
    jumps are no tool speed)."""
    top = float(browser.script("return document.getElementById('legend-max').textContent").split()[0])
    feeds = [j["peak_velocity"] for j in report["joints"]]
    check(top < 10 * max(feeds), f"{name}: the speed scale ends at {top} mm/s")


def check_narrow_window(browser, name, html):
    """At 800 px the legend and the hint lie below the drawing, not over it."""
    browser.driver.set_window_size(800, 1000)
    try:
        browser.load(html)
        scene, legend, hint = (browser.script(
            f"return document.getElementById('{element}').getBoundingClientRect().toJSON()")
            for element in ("scene", "legend", "scene-help"))
        check(legend["top"] >= scene["bottom"] - 1 and hint["top"] >= scene["bottom"] - 1,
              f"{name}: at 800 px the legend or hint covers the drawing")
    finally:
        browser.driver.set_window_size(1400, 1500)


def main():
    parser = argparse.ArgumentParser()
    for positional in ("pkm", "source", "out"):
        parser.add_argument(positional)
    parser.add_argument("--screenshots")
    parser.add_argument("--workspace-page")
    arguments = parser.parse_args()
    pkm, source, out, screenshots = (arguments.pkm, arguments.source, arguments.out,
                                     arguments.screenshots)
    os.makedirs(out, exist_ok=True)
    with open(os.path.join(out, "triaglide-square.ngc"), "w") as job:
        job.write(TRIAGLIDE_JOB)
    with open(os.path.join(out, "plotter-square.ngc"), "w") as job:
        job.write(PLOTTER_JOB)
    with open(os.path.join(out, "hangprinter-square.ngc"), "w") as job:
        job.write(HANGPRINTER_JOB)
    made = pages(pkm, source, out, arguments.workspace_page)
    browser = Browser()
    try:
        for name, kind, html, report in made:
            check_page(browser, name, kind, html, report, screenshots)
            print(f"{name}: {os.path.getsize(html) / 1e3:.0f} kB, checked")
        check_narrow_window(browser, "plotter", os.path.join(out, "plotter.html"))
    finally:
        browser.close()
    if failures:
        print(f"{len(failures)} failures")
        return 1
    print(f"all {len(made)} pages pass")
    return 0


# A square and a circle about the triaglide's home, small enough for its struts.
TRIAGLIDE_JOB = """G21 G90 G17 G64
G0 X-40 Y-40
G1 F3000 X40 Y-40
G1 X40 Y40
G1 X-40 Y40
G1 X-40 Y-40
G0 X30 Y0
G2 X30 Y0 I-30 J0 F6000
G0 X0 Y0
M2
"""

# A square drawn with the pen down, reached and left with it up (Z5: up, Z-1: down), about the
# pen plotter's home.
PLOTTER_JOB = """G21 G90
G0 Z5
G0 X700 Y-650
G1 Z-1 F600
G1 X800 F3000
G1 Y-750
G1 X700
G1 Y-650
G0 Z5
G0 X750 Y-700
M2
"""

# A 400 mm square 100 mm above the Hangprinter's origin (its home), reached from home.
HANGPRINTER_JOB = """G21 G90
G0 X-200 Y-200 Z100
G1 F6000 X200
G1 Y200
G1 X-200
G1 Y-200
M2
"""

if __name__ == "__main__":
    sys.exit(main())
