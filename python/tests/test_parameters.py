"""Machine.parameters and Machine.with_parameters: another geometry, as calibration sets one."""
import math

import numpy as np
import pytest

import pkmkit


def test_moving_hektors_right_anchor_changes_only_the_right_cable(machines):
    # Anchors at (0, 0) and (100, 0); the right one moved to (120, 5). At the pen (34, -40) the
    # left cable stays hypot(34, 40) and the right becomes hypot(120 - 34, 5 + 40).
    m = pkmkit.Machine.load(str(machines / "hektor.toml"))
    moved = m.with_parameters({"anchor_right_x": 120.0, "anchor_right_y": 5.0})
    assert moved.parameters["anchor_right_x"] == 120.0 and moved.parameters["anchor_right_y"] == 5.0
    assert m.parameters["anchor_right_x"] == 100.0  # the original is left as it was
    pose = np.array([[34.0, -40.0]])
    joints, status = moved.inverse(pose)
    assert status.tolist() == ["ok"]
    assert joints[0, 0] == pytest.approx(math.hypot(34, 40), abs=1e-12)
    assert joints[0, 1] == pytest.approx(math.hypot(86, 45), abs=1e-12)
    assert m.inverse(pose)[0][0, 1] == pytest.approx(math.hypot(66, 40), abs=1e-12)
    # FK of the new machine finds the pen again; the jacobian's right row points from the moved
    # anchor to the pen.
    back, status = moved.forward(joints)
    assert status.tolist() == ["ok"] and np.max(np.abs(back - pose)) < 1e-9
    np.testing.assert_allclose(moved.jacobian(pose[0])[1],
                               np.array([34 - 120, -40 - 5]) / math.hypot(86, 45), atol=1e-12)


def test_unchanged_parameters_give_the_same_machine(machines):
    m = pkmkit.Machine.load(str(machines / "hexapod-bit.toml"))
    same = m.with_parameters(m.parameters)
    assert same.parameters == m.parameters
    poses = m.home + np.array([[5.0, -5.0, 20.0, 1.0, 2.0, 3.0], [0.0, 10.0, -30.0, 0.0, -2.0, 0.0]])
    assert np.array_equal(same.inverse(poses)[0], m.inverse(poses)[0])
    assert (same.name, same.joint_names, same.home.tolist()) == (m.name, m.joint_names,
                                                                 m.home.tolist())


def test_unknown_parameter_and_impossible_geometry_raise(machines):
    m = pkmkit.Machine.load(str(machines / "hektor.toml"))
    with pytest.raises(KeyError, match="anchor_right_x"):  # the message lists the names
        m.with_parameters({"anchor_middle_x": 1.0})
    matrix = pkmkit.Machine.load(str(machines / "matrix-mill.toml"))
    zeros = {name: 0.0 for name in matrix.parameters}
    with pytest.raises(ValueError, match="impossible geometry"):
        matrix.with_parameters(zeros)
