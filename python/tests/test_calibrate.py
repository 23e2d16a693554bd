"""pkmkit.calibrate.fit: `pkm calibrate fit` over arrays instead of a CSV."""
import json
import subprocess

import numpy as np
import pytest

import pkmkit


def measurements(path):
    data = np.genfromtxt(path, delimiter=",", names=True)
    return (np.column_stack([data["j_left"], data["j_right"]]),
            np.column_stack([data["x"], data["y"]]))


def test_fit_equals_pkm_calibrate_fit(machines, test_data, pkm_binary, tmp_path):
    machine_file, data = machines / "hektor.toml", test_data / "hektor-measurements.csv"
    out = tmp_path / "fitted.toml"
    cli = subprocess.run([pkm_binary, "calibrate", "fit", "-m", str(machine_file), str(data), "-o",
                          str(out), "--json"], capture_output=True, text=True, check=True)
    expected = json.loads(cli.stdout)
    m = pkmkit.Machine.load(str(machine_file))
    joints, poses = measurements(data)
    fitted, report = pkmkit.calibrate.fit(m, joints, poses)
    # The same fit: lines are the CSV's there (the header is line 1) and the rows' indices here.
    assert report["max_after_line"] == expected["max_after_line"] - 2
    assert report["output"] == "" and expected["output"] == str(out)
    for key in ("max_after_line", "output"):
        del report[key], expected[key]
    assert report == expected
    assert report["rms_after_mm"] < report["rms_before_mm"] and report["converged"] is True
    # The fitted machine is the one pkm wrote: same parameters, same IK.
    written = pkmkit.Machine.load(str(out))
    assert fitted.parameters == written.parameters != m.parameters
    assert np.array_equal(fitted.inverse(poses)[0], written.inverse(poses)[0])
    assert m.parameters == pkmkit.Machine.load(str(machine_file)).parameters  # left as it was


def test_fit_of_a_known_geometry_finds_it(machines):
    # Joints computed on Hektor with its right anchor moved to (103, -1.5), poses measured
    # exactly: the fit of the anchor's two coordinates returns them.
    m = pkmkit.Machine.load(str(machines / "hektor.toml"))
    truth = m.with_parameters({"anchor_right_x": 103.0, "anchor_right_y": -1.5})
    rng = np.random.default_rng(3)
    poses = np.column_stack([rng.uniform(20, 80, 12), rng.uniform(-90, -30, 12)])
    joints, status = truth.inverse(poses)
    assert np.all(status == "ok")
    fitted, report = pkmkit.calibrate.fit(m, joints, poses, parameters=["anchor_right_*"])
    assert fitted.parameters["anchor_right_x"] == pytest.approx(103.0, abs=1e-6)
    assert fitted.parameters["anchor_right_y"] == pytest.approx(-1.5, abs=1e-6)
    assert fitted.parameters["anchor_left_x"] == m.parameters["anchor_left_x"]
    assert report["rms_after_mm"] < 1e-6 and report["measurements"] == 12
    # A coordinate not measured is NaN: every other row has x alone, and the anchor is found
    # all the same (the data are exact).
    half = poses.copy()
    half[::2, 1] = np.nan
    fitted, report = pkmkit.calibrate.fit(m, joints, half, parameters=["anchor_right_*"])
    assert report["measurements"] == 12
    assert fitted.parameters["anchor_right_x"] == pytest.approx(103.0, abs=1e-6)
    with pytest.raises(ValueError, match="poses row 0 measures nothing"):
        pkmkit.calibrate.fit(m, joints, np.full_like(poses, np.nan))
    with pytest.raises(ValueError, match=r"joints must be an \(N, 2\) array"):
        pkmkit.calibrate.fit(m, joints[:, :1], poses)


def test_a_pulley_the_data_cannot_pin_is_held_with_its_numbers(machines):
    # Hektor on GT2 pulleys measured by a camera to 0.5 mm: the pulley radius trades with the
    # cable offsets, and the data pin it to worse than a fifth of its 6.366 mm. Held there, and
    # the report says why with its numbers.
    m = pkmkit.Machine.load(str(machines / "hektor-pulleys.toml"))
    truth = m.with_parameters({"cable_offset_left": 1.0})
    rng = np.random.default_rng(4)
    poses = np.column_stack([rng.uniform(20, 80, 40), rng.uniform(-90, -30, 40)])
    joints, status = truth.inverse(poses)
    assert np.all(status == "ok")
    fitted, report = pkmkit.calibrate.fit(m, joints, poses + rng.normal(0.0, 0.5, poses.shape))
    held = {p["name"]: p for p in report["poorly_determined"]}
    pulley = held["pulley_radius"]
    assert pulley["standard_deviation"] > pulley["plausible_deviation"] == pytest.approx(0.2 * 6.366)
    assert pulley["kind"] == "a pulley's radius" and pulley["trades_with"]
    assert fitted.parameters["pulley_radius"] == 6.366
    assert "pulley_radius" in report["held"]
