#!/usr/bin/python3
# The headless "display" of a LinuxCNC run (tests/linuxcnc/run-linuxcnc puts it in [DISPLAY]
# DISPLAY; linuxcnc starts it as `drive.py -ini INIFILE`). It reads pkm-drive.json beside the
# INI file, then:
#   - samples, on the servo thread (a `sampler` component added after motion), the commanded
#     Cartesian pose (axis.L.pos-cmd), each joint's commanded position (joint.N.coarse-pos-cmd:
#     the kinematics' own output in coordinated mode, and its input in free mode), the motion
#     modes and program line, at full precision (hal.stream, not halsampler's 6 decimals);
#   - takes the machine out of E-stop, switches it on and homes every joint;
#   - jogs joints in joint mode (there and back), runs the MDI lines, then the program;
#   - records the commanded and the actual (forward kinematics of the joints) pose at rest;
#   - writes the samples (samples.csv), the rest poses (rest.csv) and what happened
#     (drive-result.json: errors from LinuxCNC's error channel, whether the program finished,
#     pkmkins' failure counters after homing and at the end).
# When LinuxCNC refuses something, the error is recorded and the run ends: the checker decides.
import csv
import json
import os
import subprocess
import sys
import time

import hal
import linuxcnc

SAMPLER_DEPTH = 20000  # 20 s of samples at a 1 ms servo period: drained every few ms


def ini_path():
    args = sys.argv[1:]
    return os.path.abspath(args[args.index("-ini") + 1])


def halcmd(*words):
    result = subprocess.run(["halcmd", *words], capture_output=True, text=True)
    if result.returncode != 0:
        raise RuntimeError("halcmd %s: %s" % (" ".join(words), result.stderr.strip()))
    return result.stdout


def signal_of(pin):
    """The signal a pin is on (made for it when it is on none)."""
    for line in halcmd("-s", "show", "pin", pin).splitlines():
        words = line.split()
        if pin in words and words[-1] != pin:
            return words[-1].lstrip("<=>")
    signal = "pkmdrive-" + pin.replace(".", "-")
    halcmd("net", signal, pin)
    return signal


class Sampler:
    """sampler.0 on the servo thread, read through hal.stream."""

    def __init__(self, columns):
        self.columns = columns  # (name, pin, type letter)
        cfg = "".join(kind for _, _, kind in columns)
        halcmd("loadrt", "sampler", "depth=%d" % SAMPLER_DEPTH, "cfg=" + cfg)
        halcmd("addf", "sampler.0", "servo-thread")
        for index, (_, pin, _) in enumerate(columns):
            halcmd("net", signal_of(pin), "sampler.0.pin.%d" % index)
        self.component = hal.component("pkmdrive")
        self.component.ready()
        self.stream = hal.stream(self.component, hal.sampler_base, cfg)
        self.rows = []

    def drain(self):
        while True:
            row = self.stream.read()
            if row is None:
                return
            self.rows.append([int(v) if isinstance(v, bool) else v for v in row])

    def overruns(self):
        return int(halcmd("-s", "getp", "sampler.0.overruns").strip() or 0)


def sample_columns(letters, joints):
    columns = [("enabled", "motion.motion-enabled", "b"),
               ("all_homed", "motion.is-all-homed", "b"),
               ("coord", "motion.coord-mode", "b"),
               ("teleop", "motion.teleop-mode", "b"),
               ("line", "motion.program-line", "s")]
    for letter in letters:
        columns.append((letter, "axis.%s.pos-cmd" % letter, "f"))
    for n in range(joints):
        columns.append(("j%d" % n, "joint.%d.coarse-pos-cmd" % n, "f"))
    return columns  # at most 5 + 6 + 9: a HAL stream takes 21 items


def counters():
    """pkmkins' failure counters (HAL pins)."""
    return {name: int(halcmd("-s", "getp", "pkmkins." + name).strip())
            for name in ("fk-failures", "ik-failures")}


class Driver:
    def __init__(self, settings):
        self.settings = settings
        self.stat = linuxcnc.stat()
        self.command = linuxcnc.command()
        self.errors = linuxcnc.error_channel()
        self.messages = []
        self.sampler = None
        self.deadline = time.monotonic() + float(settings.get("timeout_s", 120))

    def poll(self):
        self.stat.poll()
        if self.sampler:
            self.sampler.drain()
        while True:
            error = self.errors.poll()
            if not error:
                break
            kind, text = error
            self.messages.append({"kind": kind, "text": text})
            print("drive.py: LinuxCNC says (%d): %s" % (kind, text), flush=True)

    def wait(self, what, done, timeout_s=30.0):
        limit = min(self.deadline, time.monotonic() + timeout_s)
        while time.monotonic() < limit:
            self.poll()
            if done():
                return True
            time.sleep(0.005)
        raise TimeoutError("timed out waiting for " + what)

    def failed(self):
        return any(m["kind"] in (linuxcnc.NML_ERROR, linuxcnc.OPERATOR_ERROR)
                   for m in self.messages)

    def switch_on_and_home(self, joints):
        self.command.state(linuxcnc.STATE_ESTOP_RESET)
        self.wait("E-stop reset", lambda: self.stat.task_state == linuxcnc.STATE_ESTOP_RESET)
        self.command.state(linuxcnc.STATE_ON)
        self.wait("machine on", lambda: self.stat.task_state == linuxcnc.STATE_ON)
        self.command.mode(linuxcnc.MODE_MANUAL)
        self.command.wait_complete()
        self.command.home(-1)
        self.wait("homing", lambda: all(self.stat.homed[n] for n in range(joints)))

    def jog_joint(self, joint, increment, velocity):
        """A joint-mode jog there and back: in free mode motion asks the kinematics' forward for
        the commanded pose every servo cycle."""
        self.command.mode(linuxcnc.MODE_MANUAL)
        self.command.wait_complete()
        self.command.teleop_enable(0)
        self.command.wait_complete()
        self.wait("joint mode", lambda: self.stat.motion_mode == linuxcnc.TRAJ_MODE_FREE, 5.0)
        for step in (increment, -increment):
            self.command.jog(linuxcnc.JOG_INCREMENT, True, joint, velocity, step)
            self.wait("jog start", lambda: not self.stat.inpos, 2.0)
            self.wait("jog", lambda: self.stat.inpos or self.failed(), 60.0)

    def idle(self):
        return (self.stat.interp_state == linuxcnc.INTERP_IDLE and self.stat.inpos
                and self.stat.queue == 0)

    def run_mdi(self, line):
        self.command.mode(linuxcnc.MODE_MDI)
        self.command.wait_complete()
        self.command.mdi(line)
        self.command.wait_complete()
        self.wait("MDI " + line, lambda: self.idle() or self.failed(), 120.0)

    def run_program(self, path):
        self.command.mode(linuxcnc.MODE_AUTO)
        self.command.wait_complete()
        self.command.program_open(path)
        self.command.wait_complete()
        self.command.auto(linuxcnc.AUTO_RUN, 0)
        self.command.wait_complete()
        self.wait("program run", lambda: self.stat.interp_state != linuxcnc.INTERP_IDLE
                  or self.failed(), 5.0)
        self.wait("program end", lambda: self.idle() or self.failed(),
                  self.deadline - time.monotonic())

    def rest_row(self, label, joints):
        self.wait("rest", lambda: self.stat.inpos, 5.0)
        time.sleep(0.05)  # a few servo cycles: feedback and its forward kinematics settle
        self.poll()
        return ([label] + list(self.stat.position) + list(self.stat.actual_position)
                + list(self.stat.joint_position[:joints])
                + list(self.stat.joint_actual_position[:joints]))


def write_csv(path, header, rows):
    with open(path, "w", newline="") as output:
        writer = csv.writer(output, lineterminator="\n")
        writer.writerow(header)
        for row in rows:
            writer.writerow([repr(v) if isinstance(v, float) else v for v in row])


def main():
    directory = os.path.dirname(ini_path())
    with open(os.path.join(directory, "pkm-drive.json")) as settings_file:
        settings = json.load(settings_file)
    # The NML channels of the INI's [EMC] NML_FILE (the linuxcnc script exports it as NMLFILE).
    linuxcnc.nmlfile = os.environ.get("NMLFILE", linuxcnc.nmlfile)
    driver = Driver(settings)
    result = {"finished": False, "homed": False}
    rest = []
    joints = 0
    try:
        driver.poll()
        ini = linuxcnc.ini(ini_path())
        joints = int(ini.find("KINS", "JOINTS"))
        letters = []
        for letter in ini.find("TRAJ", "COORDINATES").lower():
            if letter in "xyzabcuvw" and letter not in letters:
                letters.append(letter)
        columns = sample_columns(letters, joints)
        driver.sampler = Sampler(columns)
        driver.switch_on_and_home(joints)
        result["homed"] = True
        result["counters_at_homing"] = counters()
        rest.append(driver.rest_row("homed", joints))
        for joint, increment, velocity in settings.get("jog", []):
            driver.jog_joint(joint, increment, velocity)
            if driver.failed():
                break
            rest.append(driver.rest_row("jog joint %d" % joint, joints))
        for line in settings.get("mdi", []):
            driver.run_mdi(line)
            if driver.failed():
                break
            rest.append(driver.rest_row("mdi " + line, joints))
        if settings.get("program") and not driver.failed():
            driver.run_program(os.path.join(directory, settings["program"]))
            if not driver.failed():
                rest.append(driver.rest_row("program end", joints))
        result["finished"] = not driver.failed()
    except Exception as error:  # the run's outcome, for the checker and the log
        result["exception"] = "%s: %s" % (type(error).__name__, error)
        print("drive.py:", result["exception"], flush=True)
    time.sleep(0.1)
    driver.poll()
    result["task_state"] = driver.stat.task_state
    try:
        result["counters_at_end"] = counters()
    except RuntimeError as error:
        print("drive.py:", error, flush=True)
    result["messages"] = driver.messages
    if driver.sampler:
        result["sampler_overruns"] = driver.sampler.overruns()
        write_csv(os.path.join(directory, "samples.csv"),
                  [name for name, _, _ in driver.sampler.columns], driver.sampler.rows)
        result["samples"] = len(driver.sampler.rows)
    letters = "x y z a b c u v w".split()
    write_csv(os.path.join(directory, "rest.csv"),
              ["label"] + ["cmd_" + l for l in letters] + ["act_" + l for l in letters]
              + ["j%d" % n for n in range(joints)] + ["j%d_act" % n for n in range(joints)],
              rest)
    with open(os.path.join(directory, "drive-result.json"), "w") as output:
        json.dump(result, output, indent=1)
    driver.command.state(linuxcnc.STATE_OFF)


if __name__ == "__main__":
    main()
