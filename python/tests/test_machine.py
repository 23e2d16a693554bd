"""pkmkit.Machine: loading a machine file, its properties, and the errors of a malformed one."""
import math
import subprocess

import numpy as np
import pytest

import pkmkit


def test_hektor_properties(machines):
    m = pkmkit.Machine.load(str(machines / "hektor.toml"))
    assert m.name == "Hektor (source document, d = 100)"
    assert m.kinematics == "cable_plotter"
    assert m.dof == 2
    assert m.coordinates == ["x", "y"]
    assert m.joint_names == ["left", "right"]
    left = m.joints[0]
    assert (left.name, left.min, left.max, left.unit, left.kind) == ("left", 5.0, 180.0, "mm",
                                                                      "linear")
    assert m.home.tolist() == [50.0, -50.0]
    # anchor_distance = 100 puts the right anchor at (100, 0).
    assert (m.parameters["anchor_right_x"], m.parameters["anchor_right_y"]) == (100.0, 0.0)
    assert m.parameter_units["anchor_right_x"] == "mm"


def test_hexapod_home_and_envelope(machines):
    m = pkmkit.Machine.load(str(machines / "hexapod-bit.toml"))
    assert m.dof == 6
    assert m.coordinates == ["x", "y", "z", "a", "b", "c"]
    assert m.home.tolist() == [0.0, 0.0, 1000.0, 0.0, 0.0, 0.0]
    low, high = m.envelope
    assert low.shape == (6,) and np.all(np.isinf(low)) and np.all(np.isinf(high))


def test_hektor_inverse_matches_the_worked_example(machines):
    # The Mach3 document's example: x = 34, y = -40 gives a = 52.498, b = 77.175; by hand,
    # a = hypot(34, 40), b = hypot(100 - 34, 40).
    m = pkmkit.Machine.load(str(machines / "hektor.toml"))
    joints, status = m.inverse(np.array([[34.0, -40.0]]))
    assert status.tolist() == ["ok"]
    assert joints[0, 0] == pytest.approx(math.hypot(34, 40), abs=1e-12)
    assert joints[0, 1] == pytest.approx(math.hypot(66, 40), abs=1e-12)
    assert round(joints[0, 0], 3) == 52.498 and round(joints[0, 1], 3) == 77.175


def test_jacobian_in_mm_per_mm(machines):
    # d left / d (x, y) is the unit vector from the left anchor (0, 0) to the pen.
    m = pkmkit.Machine.load(str(machines / "hektor.toml"))
    jacobian = m.jacobian(np.array([30.0, -40.0]))
    assert jacobian.shape == (2, 2)
    np.testing.assert_allclose(jacobian[0], [0.6, -0.8], atol=1e-12)


def test_hexapod_jacobian_angle_columns_per_degree(machines):
    # A finite difference over 1e-4 deg of c agrees with the column per degree.
    m = pkmkit.Machine.load(str(machines / "hexapod-bit.toml"))
    pose = np.array([10.0, -20.0, 1000.0, 2.0, -3.0, 5.0])
    step = 1e-4
    above, below = pose.copy(), pose.copy()
    above[5] += step
    below[5] -= step
    joints, status = m.inverse(np.array([above, below]))
    assert status.tolist() == ["ok", "ok"]
    np.testing.assert_allclose(m.jacobian(pose)[:, 5], (joints[0] - joints[1]) / (2 * step),
                               atol=1e-6)


def test_malformed_machine_file_raises_with_file_line_key(machines, pkm_binary, tmp_path):
    # Hektor's file with a word where line 9 wants a number: the same located message as pkm's.
    text = (machines / "hektor.toml").read_text()
    assert text.splitlines()[8] == "anchor_distance = 100.0"
    path = tmp_path / "broken.toml"
    path.write_text(text.replace("anchor_distance = 100.0", 'anchor_distance = "wide"'))
    with pytest.raises(pkmkit.MachineFileError) as raised:
        pkmkit.Machine.load(str(path))
    message = str(raised.value)
    assert message == f"{path}:9:kinematics.anchor_distance: must be a number"
    assert (raised.value.file, raised.value.line,
            raised.value.key) == (str(path), 9, "kinematics.anchor_distance")
    assert isinstance(raised.value, ValueError)
    cli = subprocess.run([pkm_binary, "ik", "-m", str(path), "50", "-50"],
                         capture_output=True, text=True)
    assert cli.returncode != 0 and message in cli.stderr


def test_missing_machine_file_raises(tmp_path):
    with pytest.raises(pkmkit.MachineFileError, match="nothing.toml"):
        pkmkit.Machine.load(str(tmp_path / "nothing.toml"))


def test_wrong_pose_shape_raises(machines):
    m = pkmkit.Machine.load(str(machines / "hektor.toml"))
    with pytest.raises(ValueError, match=r"\(N, 2\)"):
        m.inverse(np.zeros((4, 3)))


@pytest.mark.filterwarnings("ignore::pkmkit.CopyWarning")
def test_other_layouts_and_types_are_converted(machines):
    # C-contiguous float64 is read in place; anything else (lists, ints, Fortran order, a strided
    # view) is converted first, to the same answer.
    m = pkmkit.Machine.load(str(machines / "hexapod-bit.toml"))
    poses = m.home + np.array([[5.0, -5.0, 20.0, 1.0, 2.0, 3.0], [0.0, 10.0, -30.0, 0.0, -2.0, 0.0]])
    expected, _ = m.inverse(poses)
    for variant in (np.asfortranarray(poses), poses.tolist(), np.repeat(poses, 2, axis=0)[::2]):
        joints, status = m.inverse(variant)
        assert np.array_equal(joints, expected) and status.tolist() == ["ok", "ok"]
    joints, _ = m.inverse(np.rint(poses).astype(np.int64))
    np.testing.assert_array_equal(joints, m.inverse(np.rint(poses))[0])


def test_statuses_are_the_status_code_identifiers():
    assert len(pkmkit.STATUSES) == 12
    assert pkmkit.STATUSES[:3] == ("ok", "unreachable", "joint_limit")
    assert pkmkit.STATUSES[-1] == "interference"
