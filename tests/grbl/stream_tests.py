#!/usr/bin/env python3
"""pkm stream against grbl 1.1h (grbl-sim on a pty) and against ports that are not grbl.

usage: stream_tests.py CASE PKM GRBL_SIM SOURCE_DIR WORK_DIR

Cases: ends_where_the_job_ends, refused_line, garbage_port, interrupt. Each runs in a few
seconds of wall time (grbl-sim simulates 16 MHz of AVR: about real time on an idle machine).
"""
import math
import os
import re
import select
import signal
import subprocess
import sys
import threading
import time

CASE, PKM, GRBL_SIM, SOURCE, WORK = sys.argv[1:6]
MACHINE = os.path.join(SOURCE, "examples/machines/wall-plotter.toml")
DATA = os.path.join(SOURCE, "tests/data")
HOME = (750.0, -700.0)  # the wall plotter's home pose, mm: grbl-sim is zeroed there


def steps_per_mm():
    """Each joint's steps_per_unit in the machine file, else grbl's default 250 (pkm stream sends
    no $100 then)."""
    text = open(MACHINE).read()
    joints = text.split("[[joints]]")[1:]
    values = []
    for joint in joints:
        joint = joint.split("\n[")[0]
        found = re.search(r"^steps_per_unit\s*=\s*([0-9.eE+-]+)", joint, re.M)
        values.append(float(found.group(1)) if found else 250.0)
    return values


STEPS_PER_MM = steps_per_mm()
SIM_CLOCK = "0.25"  # a quarter of real time: grbl-sim keeps up even on a loaded CI machine
os.makedirs(WORK, exist_ok=True)


def fail(message):
    print("FAIL: " + message)
    sys.exit(1)


def run(arguments, timeout=60):
    return subprocess.run([PKM] + arguments, capture_output=True, text=True, timeout=timeout)


def stream(arguments, timeout=60):
    return run(["stream", "-m", MACHINE, "--dry-run", "--grbl-sim", GRBL_SIM, "--sim-clock",
                SIM_CLOCK] + arguments, timeout)


def joints_at(pose):
    out = run(["ik", "-m", MACHINE, str(pose[0]), str(pose[1])]).stdout
    return [float(v) for v in re.findall(r"= (-?[0-9.]+) mm", out)]


def pose_at(joints):
    out = run(["fk", "-m", MACHINE] + ["%.6f" % j for j in joints]).stdout
    return [float(v) for v in re.findall(r"= (-?[0-9.]+) mm", out)]


def last_steps(path):
    rows = [line.split() for line in open(path) if line.strip()]
    return [int(rows[-1][1].rstrip(",")), int(rows[-1][2].rstrip(","))]


def ends_where_the_job_ends():
    # The square's job ends 3 mm right and 3 mm up of its start, which --origin puts at home.
    steps_file = os.path.join(WORK, "square.steps")
    result = stream([os.path.join(DATA, "grbl-small-square.ngc"), "--origin", "750", "-700",
                     "--record-steps", steps_file])
    if result.returncode != 0:
        fail("stream failed: " + result.stderr)
    # grbl reports its position in whole steps of each cord (0.0125 mm at 80 steps/mm), to
    # 0.001 mm: FK of that is within post's tolerance and a step's worth of the pose.
    reported = re.search(r"every one answered ok, at Idle  x (-?[0-9.]+) y (-?[0-9.]+) mm",
                         result.stdout)
    one_step = max(1.0 / k for k in STEPS_PER_MM) / math.sin(math.radians(86.0))
    if not reported or max(abs(float(reported.group(1)) - 753.0),
                           abs(float(reported.group(2)) + 697.0)) > 0.01 + one_step:
        fail("summary: " + result.stdout)
    if os.path.exists(steps_file + ".partial"):
        fail("the step record was left under its temporary name")
    home = joints_at(HOME)
    joints = [h + s / k for h, s, k in zip(home, last_steps(steps_file), STEPS_PER_MM)]
    pose = pose_at(joints)
    # One step of either cord moves the pen by at most (1 / steps per mm) / sin(angle between the
    # cords): at home the cords meet at 86 deg (0.0041 mm at 250 steps/mm); post's tolerance
    # 0.01 mm on top.
    one_step = max(1.0 / k for k in STEPS_PER_MM) / math.sin(math.radians(86.0))
    error = max(abs(pose[0] - 753.0), abs(pose[1] + 697.0))
    if error > 0.01 + one_step:
        fail("grbl stopped at x %.4f y %.4f mm, the job ends at x 753 y -697 (%.4f mm off)" %
             (pose[0], pose[1], error))
    print("ok: grbl ends at x %.4f y %.4f mm (%.4f mm from the job's end)" %
          (pose[0], pose[1], error))


def refused_line():
    result = stream([os.path.join(DATA, "grbl-refused-line.ngc"), "--joint-program"])
    expected = ("grbl-sim: grbl refused line 4: G12 X1026: error:20: a G or M code grbl does "
                "not support")
    if result.returncode == 0 or expected not in result.stderr:
        fail("exit %d, stderr: %s" % (result.returncode, result.stderr))
    if "feed held" not in result.stderr or "then grbl was reset" not in result.stderr:
        fail("no clean stop: " + result.stderr)
    print("ok: " + result.stderr.strip().splitlines()[-1])


def garbage_port():
    # A pty whose other end writes noise, as a wrong device or a wrong baud rate does.
    master, slave = os.openpty()
    device = os.ttyname(slave)
    stop = threading.Event()

    def noise():
        while not stop.is_set():
            try:
                os.write(master, b"\x8f\xfe~garbage\x00\r\n")
                while True:  # swallow what pkm sends, so that its writes never block
                    ready, _, _ = select.select([master], [], [], 0.05)
                    if not ready:
                        break
                    os.read(master, 1024)
            except OSError:
                return
            time.sleep(0.2)

    thread = threading.Thread(target=noise, daemon=True)
    thread.start()
    start = time.monotonic()
    result = run(["stream", "-m", MACHINE, os.path.join(DATA, "grbl-small-square.ngc"),
                  "--origin", "750", "-700", "--port", device], timeout=30)
    took = time.monotonic() - start
    stop.set()
    expected = device + ": no grbl banner"
    if result.returncode == 0 or expected not in result.stderr or "garbage" not in result.stderr:
        fail("exit %d, stderr: %s" % (result.returncode, result.stderr))
    if took > 15:
        fail("took %.1f s" % took)
    print("ok in %.1f s: %s" % (took, result.stderr.strip()))


def interrupt():
    steps_file = os.path.join(WORK, "interrupted.steps")
    process = subprocess.Popen(
        [PKM, "stream", "-m", MACHINE, "--dry-run", "--grbl-sim", GRBL_SIM, "--sim-clock", SIM_CLOCK,
         os.path.join(DATA, "grbl-long-line.ngc"), "--origin", "750", "-700",
         "--record-steps", steps_file], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    # Ctrl-C once the pen has moved 1 mm (250 steps) along the first line, 2 mm/s of wall time.
    deadline = time.monotonic() + 40
    while time.monotonic() < deadline:
        try:
            if abs(last_steps(steps_file + ".partial")[0]) >= 250:
                break
        except (OSError, IndexError, ValueError):
            pass
        time.sleep(0.05)
    process.send_signal(signal.SIGINT)
    try:
        out, err = process.communicate(timeout=20)
    except subprocess.TimeoutExpired:
        process.kill()
        fail("pkm stream did not end 20 s after Ctrl-C")
    if process.returncode == 0 or "stopped by Ctrl-C after" not in err:
        fail("exit %d, stderr: %s" % (process.returncode, err))
    # Held to a stop (Hold:0) before the reset: grbl keeps its position, raises no alarm.
    if "feed held (grbl: Hold:0), then grbl was reset" not in err or "ALARM" in err:
        fail("not a clean stop: " + err)
    steps = last_steps(steps_file)
    joints = [h + s / k for h, s, k in zip(joints_at(HOME), steps, STEPS_PER_MM)]
    pose = pose_at(joints)
    # Stopped on the first line (y = -700), short of its end at x 770.
    if not (750.1 < pose[0] < 769.9) or abs(pose[1] + 700.0) > 0.02:
        fail("stopped at x %.4f y %.4f mm: not part-way along the first line" % tuple(pose))
    print("ok: stopped at x %.3f y %.3f mm; %s" % (pose[0], pose[1], err.strip().splitlines()[-1]))


{"ends_where_the_job_ends": ends_where_the_job_ends, "refused_line": refused_line,
 "garbage_port": garbage_port, "interrupt": interrupt}[CASE]()
