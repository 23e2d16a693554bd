"""pkmkit.canon: the canonical commands of `pkm gcode --canon`, field for field."""
import os
import pathlib
import subprocess

import pytest

import pkmkit

# The real G-code corpus, outside the repository (tests/CMakeLists.txt, PKM_REAL_CORPUS).
REAL = pathlib.Path(os.environ.get("PKM_REAL_CORPUS",
                                   pathlib.Path(__file__).resolve().parents[3] / "shared/gcode/real"))
# A real program (LinuxCNC's torture test: helical arcs in all three planes, comments between
# words, a message, M0) and its backplot test (full circles in three planes, inch, N numbers).
PROGRAMS = [REAL / "linuxcnc" / "tort.ngc", REAL / "linuxcnc" / "3dtest.ngc"]

PLANE_AXES = {"xy": (0, 1, 2), "xz": (2, 0, 1), "yz": (1, 2, 0)}


def canon_text(c):
    """rs274 -g's text of a command, from the named tuple's fields (what canon_text in C++ does
    for the kinds these programs have): the fields must mean what they say."""
    six = ", ".join(f"{v:.4f}" for v in c.end[:6])
    simple = {"traverse": f"STRAIGHT_TRAVERSE({six})", "feed": f"STRAIGHT_FEED({six})",
              "dwell": f"DWELL({c.value:.4f})", "set_feed_rate": f"SET_FEED_RATE({c.value:.4f})",
              "set_feed_mode": "SET_FEED_MODE(0, " +
                               ("1)" if c.feed_mode == "units_per_revolution" else "0)"),
              "comment": f'COMMENT("{c.text}")', "message": f'MESSAGE("{c.text}")',
              "program_stop": "PROGRAM_STOP()", "program_end": "PROGRAM_END()",
              "select_plane": f"SELECT_PLANE(CANON_PLANE_{c.plane.upper()})",
              "use_length_units": "USE_LENGTH_UNITS(CANON_UNITS_" +
                                  ("MM)" if c.units == "mm" else "INCHES)"),
              "spindle_speed": f"SET_SPINDLE_SPEED(0, {c.value:.4f})",
              "spindle_clockwise": "START_SPINDLE_CLOCKWISE(0)",
              "spindle_stop": "STOP_SPINDLE_TURNING(0)",
              "select_tool": f"SELECT_TOOL({c.integer})", "change_tool": f"CHANGE_TOOL({c.integer})",
              "g5x_offset": f"SET_G5X_OFFSET({c.integer}, {six})",
              "g92_offset": f"SET_G92_OFFSET({six})"}
    if c.kind in simple:
        return simple[c.kind]
    if c.kind == "arc":
        first, second, normal = PLANE_AXES[c.plane]
        e = c.end
        return (f"ARC_FEED({e[first]:.4f}, {e[second]:.4f}, {c.center[0]:.4f}, {c.center[1]:.4f}, "
                f"{c.turns}, {e[normal]:.4f}, {e[3]:.4f}, {e[4]:.4f}, {e[5]:.4f})")
    if c.kind == "path_control" and c.integer == 64:
        return f"SET_MOTION_CONTROL_MODE(CANON_CONTINUOUS, {c.value:.6f})"
    raise AssertionError(f"the test has no text for {c.kind}")


@pytest.mark.parametrize("program", PROGRAMS, ids=[p.name for p in PROGRAMS])
def test_canon_equals_pkm_gcode_canon(pkm_binary, program):
    if not program.exists():
        pytest.skip(f"{program}: the real G-code corpus is not on this machine")
    cli = subprocess.run([pkm_binary, "gcode", "--canon", str(program)], capture_output=True,
                         text=True, check=True)
    expected = cli.stdout.splitlines()[6:]  # after rs274's preamble
    commands = list(pkmkit.canon(str(program)))
    assert len(commands) == len(expected) > 50
    for c, line in zip(commands, expected):
        label = "N" + (f"{c.n:<5}" if c.n else ".....")
        assert line[6:] == f"{label} {canon_text(c)}"


def test_canon_fields_of_a_small_program(tmp_path):
    job = tmp_path / "job.ngc"
    job.write_text("G20 G90 F30\n(cut)\nN10 G1 X1 Y2\nG3 X3 Y2 I1 J0\nM2\n")
    commands = pkmkit.canon(str(job))
    assert iter(commands) is commands
    kinds = [(c.kind, c.line) for c in commands]
    # rs274's order: the feed rate before the units on line 1; M2 resets the offsets, the feed
    # mode and rate and the spindle before the end.
    assert kinds == [("set_feed_rate", 1), ("use_length_units", 1), ("comment", 2), ("feed", 3),
                     ("arc", 4), ("g5x_offset", 5), ("g92_offset", 5), ("set_feed_mode", 5),
                     ("set_feed_rate", 5), ("spindle_stop", 5), ("program_end", 5)]
    feed_rate, units, comment, feed, arc, *_ = pkmkit.canon(str(job))
    assert units.units == "inch" and feed_rate.value == 30.0 and comment.text == "cut"
    assert feed.n == "10" and feed.end[:3] == (1.0, 2.0, 0.0) and len(feed.end) == 9
    # The F in effect, in the move's units: F30 was read in mm/min (rs274 sets the feed before the
    # units of the same line), which is 30 / 25.4 inch/min once G20 is in effect.
    assert feed.units == "inch" and feed.value == pytest.approx(30.0 / 25.4, rel=1e-15)
    assert arc.plane == "xy" and arc.center == (2.0, 2.0) and arc.turns == 1
    assert arc.end[:2] == (3.0, 2.0)
    assert isinstance(arc, tuple) and arc._fields[0] == "kind"


def test_canon_of_a_move_fed_per_revolution(tmp_path):
    job = tmp_path / "thread.ngc"
    job.write_text("G21 G18 S500 M3\nG33 Z-10 K1.5\nM2\n")
    sync, feed, stop = [c for c in pkmkit.canon(str(job)) if c.line == 2]
    assert (sync.kind, sync.value, stop.kind) == ("speed_feed_sync", 1.5, "speed_feed_sync_stop")
    assert (feed.kind, feed.feed_mode, feed.value, feed.spindle_rpm) == (
        "feed", "units_per_revolution", 1.5, 500.0)


def test_canon_error_is_raised_where_the_iterator_reaches_it(tmp_path):
    job = tmp_path / "bad.ngc"
    job.write_text("G21\nG1 X1 F100\nG1 X2 Q\nM2\n")
    commands = pkmkit.canon(str(job))
    assert [c.kind for c in (next(commands), next(commands), next(commands))] == [
        "use_length_units", "set_feed_rate", "feed"]
    with pytest.raises(pkmkit.GcodeError) as raised:
        next(commands)
    assert (raised.value.file, raised.value.line) == (str(job), 3)
    assert str(raised.value).startswith(f"{job}:3:")
    with pytest.raises(pkmkit.GcodeError):
        pkmkit.canon(str(tmp_path / "none.ngc"))
