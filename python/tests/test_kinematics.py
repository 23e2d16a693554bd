"""Batch kinematics: IK equals `pkm ik`, FK round trips, refused poses, threads."""
import json
import subprocess
import sys
import threading
import time
import warnings

import numpy as np
import pytest

import pkmkit

# A few poses (mm, deg; the machine's coordinates) of three example machines.
POSES = {
    "hektor.toml": [[34.0, -40.0], [50.0, -50.0], [10.25, -120.5], [90.0, -15.0]],
    "hexapod-bit.toml": [[0.0, 0.0, 1000.0, 0.0, 0.0, 0.0], [12.5, -30.0, 950.0, 3.0, -2.0, 10.0],
                         [-80.0, 45.0, 1100.0, -5.0, 4.5, -20.0]],
    "triaglide.toml": [[0.0, 0.0, 200.0], [100.0, 50.0, 250.0], [-60.5, -30.25, 180.0]],
}


def pkm_ik(pkm_binary, machine_file, pose):
    """`pkm ik --json` of one pose: the joint values it prints."""
    result = subprocess.run(
        [pkm_binary, "ik", "-m", str(machine_file), "--json", "--", *map(repr, pose)],
        capture_output=True, text=True, check=True)
    return json.loads(result.stdout)["joints"]


@pytest.mark.parametrize("name", sorted(POSES))
def test_batch_inverse_equals_pkm_ik(machines, pkm_binary, name):
    m = pkmkit.Machine.load(str(machines / name))
    poses = np.array(POSES[name])
    joints, status = m.inverse(poses)
    assert joints.shape == (len(poses), len(m.joints))
    assert status.tolist() == ["ok"] * len(poses)
    for row, pose in enumerate(POSES[name]):
        assert joints[row].tolist() == pkm_ik(pkm_binary, machines / name, pose)


def test_inverse_speaks_mm_and_deg_whatever_the_file_says(machines, pkm_binary):
    # pkm ik speaks the file's units and takes x y z a b c in order; pkmkit takes mm and deg over
    # the controlled coordinates only. An inch rotary delta (joints in deg) and a 5-axis table
    # (x y z a c, no b).
    rdelta = pkmkit.Machine.load(str(machines / "linuxcnc-rdelta.toml"))
    pose_mm = [25.4, -12.7, -270.0]
    joints, status = rdelta.inverse(np.array([pose_mm]))
    assert status.tolist() == ["ok"] and [j.unit for j in rdelta.joints] == ["deg"] * 3
    expected = pkm_ik(pkm_binary, machines / "linuxcnc-rdelta.toml", [1.0, -0.5, -270.0 / 25.4])
    np.testing.assert_allclose(joints[0], expected, rtol=0, atol=1e-9)
    table = pkmkit.Machine.load(str(machines / "linuxcnc-xyzac-trt.toml"))
    assert table.coordinates == ["x", "y", "z", "a", "c"]
    joints, status = table.inverse(np.array([[10.0, 20.0, 90.0, -30.0, 45.0]]))
    assert status.tolist() == ["ok"]
    expected = pkm_ik(pkm_binary, machines / "linuxcnc-xyzac-trt.toml",
                      [10.0, 20.0, 90.0, -30.0, 0.0, 45.0])
    assert joints[0].tolist() == expected


def test_forward_round_trip_on_100000_hexapod_poses(machines):
    m = pkmkit.Machine.load(str(machines / "hexapod-bit.toml"))
    rng = np.random.default_rng(15)
    count = 100_000
    spread = np.array([50.0, 50.0, 50.0, 5.0, 5.0, 5.0])  # mm and deg around home
    poses = m.home + rng.uniform(-1.0, 1.0, (count, 6)) * spread
    joints, status = m.inverse(poses)
    assert np.all(status == "ok")
    back, status = m.forward(joints)
    assert np.all(status == "ok")
    assert np.max(np.abs(back[:, :3] - poses[:, :3])) <= 1e-9  # mm
    assert np.max(np.abs(back[:, 3:] - poses[:, 3:])) <= 1e-9  # deg


def test_forward_with_seed_and_single_row(machines):
    m = pkmkit.Machine.load(str(machines / "triaglide.toml"))
    pose = np.array([[40.0, -25.0, 230.0]])
    joints, _ = m.inverse(pose)
    back, status = m.forward(joints, seed=np.array([0.0, 0.0, 200.0]))
    assert status.tolist() == ["ok"]
    np.testing.assert_allclose(back, pose, atol=1e-9)


def test_forward_along_a_helix_past_the_struts_plane_fails_only_the_bad_row(machines):
    # A helix of radius 20 mm whose start is the pose of issue 25's reproducer, where the
    # triaglide's two sphere intersections are 0.09 mm apart across the struts' plane. FK used to
    # choose between them by the seed's side of the spheres' centres: rows near that plane went to
    # the mirror image and failed (110 in a row here, each seeded with the last good pose). One
    # row of joints no strut reaches in the middle fails alone; the row after it is solved.
    m = pkmkit.Machine.load(str(machines / "triaglide.toml"))
    start = np.array([-69.5847887844257, 39.47456913822882, 174.17930640982385])
    turn = np.linspace(0.0, 4.0 * np.pi, 10_000)
    centre = start - np.array([0.0, 20.0, 0.0])
    poses = np.stack([centre[0] + 20.0 * np.cos(turn + np.pi / 2),
                      centre[1] + 20.0 * np.sin(turn + np.pi / 2),
                      start[2] + 5.0 * turn / (2.0 * np.pi)], axis=1)
    joints, status = m.inverse(poses)
    assert np.all(status == "ok")
    bad = len(poses) // 2
    joints[bad] = [-400.0, 800.0, -400.0]  # within the rails' limits, too far apart to meet
    back, status = m.forward(joints)
    assert status[bad] == "unreachable"
    rest = np.arange(len(poses)) != bad
    assert np.all(status[rest] == "ok"), np.flatnonzero(status != "ok")[:10]
    # Within 1e-9 mm, but where the pose is so near the struts' plane that the joints, rounded
    # to doubles (1e-13 mm or so), pin it down less well: 1e-12 mm over the smallest singular
    # value of d joints / d pose (6.5e-5 at the first row: 1.5e-8 mm, a wrong branch is 0.09 mm
    # off).
    error = np.max(np.abs(back - poses), axis=1)
    for row in np.flatnonzero(rest & (error > 1e-9)):
        smallest = np.linalg.svd(m.jacobian(poses[row]), compute_uv=False)[-1]
        assert error[row] <= 1e-12 / smallest, (row, error[row], smallest)
    assert np.count_nonzero(error > 1e-9) < 10


def test_refused_poses_give_their_status_and_finite_joints(machines, pkm_binary):
    m = pkmkit.Machine.load(str(machines / "hektor.toml"))
    # The second pose needs 500 mm of belt (max 180); the third is not a number.
    poses = np.array([[34.0, -40.0], [50.0, -500.0], [np.nan, -40.0]])
    joints, status = m.inverse(poses)
    assert status.tolist() == ["ok", "joint_limit", "invalid_input"]
    assert np.all(np.isfinite(joints))
    assert joints[1:].tolist() == [[0.0, 0.0], [0.0, 0.0]]
    refused = subprocess.run([pkm_binary, "ik", "-m", str(machines / "hektor.toml"), "50", "-500"],
                             capture_output=True, text=True)
    assert refused.returncode != 0 and "joint" in refused.stderr


def test_forward_refuses_joints_past_their_limits(machines):
    m = pkmkit.Machine.load(str(machines / "hektor.toml"))
    poses, status = m.forward(np.array([[52.0, 77.0], [200.0, 77.0]]))
    assert status.tolist() == ["ok", "joint_limit"]
    assert poses[1].tolist() == [0.0, 0.0]


@pytest.mark.parametrize("name", ["hexapod-bit.toml", "mach3-formula.toml"])
def test_two_threads_run_batch_inverse_at_once(machines, name):
    # Both threads share one machine and start their batches together (a barrier); the batch
    # loop runs without the GIL, so they overlap, and each works on its own copy of the machine:
    # both results equal one single-threaded call's. (Whether they overlap is not asserted: that
    # would take timing.)
    # A formula machine's evaluator keeps state per call: the case a shared machine would break.
    m = pkmkit.Machine.load(str(machines / name))
    rng = np.random.default_rng(7)
    poses = m.home + rng.uniform(-1.0, 1.0, (20_000, m.dof)) * 4.0
    expected, expected_status = m.inverse(poses)
    results = [None, None]
    started = threading.Barrier(2)

    def run(slot):
        started.wait()
        results[slot] = m.inverse(poses)

    threads = [threading.Thread(target=run, args=(slot,)) for slot in range(2)]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join()
    assert np.all(expected_status == "ok")
    for joints, status in results:
        assert np.array_equal(joints, expected)
        assert np.array_equal(status, expected_status)


def count_while_calling(call):
    """How far a Python thread counts while `call` runs in this thread.

    The switch interval is made so long that a thread holding the GIL keeps it: the counter
    thread can only run where this thread lets the GIL go. It is let go by the call (if at all)
    and by nothing else between the start signal and the read after the call returns.
    """
    counter = [0]
    go, stop = threading.Event(), threading.Event()

    def count():
        go.wait()
        while not stop.is_set():
            counter[0] += 1
            time.sleep(1e-4)  # lets the GIL go, so the caller gets it back when the call ends

    interval = sys.getswitchinterval()
    thread = threading.Thread(target=count)
    thread.start()
    sys.setswitchinterval(1000.0)
    try:
        go.set()
        result = call()
        counted = counter[0]
    finally:
        stop.set()
        sys.setswitchinterval(interval)
        thread.join()
    return counted, result


def test_a_python_thread_runs_while_batch_calls_run(machines):
    # Without the GIL released the count would be 0: the counter thread cannot start before the
    # call (this thread holds the GIL from go.set() on) and the count is read right after it.
    m = pkmkit.Machine.load(str(machines / "hexapod-bit.toml"))
    rng = np.random.default_rng(5)
    poses = m.home + rng.uniform(-1.0, 1.0, (1_000_000, 6)) * 4.0
    counted, (joints, status) = count_while_calling(lambda: m.inverse(poses))
    assert counted > 0 and np.all(status == "ok")
    counted, (back, status) = count_while_calling(lambda: m.forward(joints[:100_000]))
    assert counted > 0 and np.all(status == "ok")
    counted, _ = count_while_calling(lambda: sum(range(1_000_000)))
    assert counted == 0  # the method's control: a call that keeps the GIL lets nobody count


def test_contiguous_input_is_not_copied_other_input_is_with_a_warning(machines):
    m = pkmkit.Machine.load(str(machines / "hektor.toml"))
    poses = np.array([[34.0, -40.0], [50.0, -50.0], [10.0, -60.0], [60.0, -20.0]])
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # a CopyWarning would raise
        expected, _ = m.inverse(poses)
        m.inverse(poses[1:3])  # a slice of rows is still C-contiguous
        m.inverse(poses.tolist())  # a list must be converted: no warning for it
        m.forward(np.ascontiguousarray(expected))
    for copied in (np.asfortranarray(poses), np.repeat(poses, 2, axis=0)[::2],
                   poses.astype(np.float32)):
        with pytest.warns(pkmkit.CopyWarning, match="poses is not a C-contiguous float64"):
            joints, _ = m.inverse(copied)
        np.testing.assert_allclose(joints, expected, atol=1e-4)
    with pytest.warns(pkmkit.CopyWarning, match="joints is not"):
        m.forward(np.asfortranarray(expected))


# The N-cable robot (type = "cable_robot"): IK equals `pkm ik`, FK of a line read long refuses the
# row, and Machine.tensions gives the tension distribution, checked by the balance it must satisfy
# (sum of t_i u_i = m g straight up, u_i the unit vector to anchor i), independently of pkm.
HANGPRINTER_ANCHORS = np.array([[0.0, -1610.98, -131.53], [1314.22, 1268.14, -121.28],
                                [-1415.73, 707.61, -121.82], [0.0, 0.01, 2299.83]])


def test_cable_robot_inverse_forward_and_tensions(machines, pkm_binary):
    m = pkmkit.Machine.load(str(machines / "hangprinter-v4.toml"))
    poses = np.array([[0.0, 0.0, 0.0], [-200.0, -200.0, 100.0], [150.0, 50.0, 300.0]])
    joints, status = m.inverse(poses)
    assert status.tolist() == ["ok"] * 3
    # Each line's length is |anchor - tool| (the tie points are the tool point).
    expected = np.linalg.norm(HANGPRINTER_ANCHORS[None, :, :] - poses[:, None, :], axis=2)
    np.testing.assert_allclose(joints, expected, rtol=0, atol=1e-9)
    for row, pose in enumerate(poses.tolist()):
        assert joints[row].tolist() == pkm_ik(pkm_binary, machines / "hangprinter-v4.toml", pose)
    back, status = m.forward(joints)
    assert status.tolist() == ["ok"] * 3
    np.testing.assert_allclose(back, poses, rtol=0, atol=1e-9)
    # Line B read 5 mm long at home: no pose fits the four lines within misfit_tolerance.
    misread = joints[:1].copy()
    misread[0, 1] += 5.0
    _, status = m.forward(misread)
    assert status.tolist() == ["unreachable"]

    tensions, held = m.tensions(poses)
    assert tensions.shape == (3, 4) and held.tolist() == [True] * 3
    # At home: the distribution nearest 35 N each (docs/cable-machines.md, "N cables").
    np.testing.assert_allclose(tensions[0], [39.6545, 37.5787, 30.2545, 17.8454], atol=5e-5)
    for pose, t in zip(poses, tensions):
        towards = HANGPRINTER_ANCHORS - pose
        units = towards / np.linalg.norm(towards, axis=1)[:, None]
        np.testing.assert_allclose(units.T @ t, [0.0, 0.0, 1.0 * 9.80665], rtol=0, atol=1e-9)
        assert (t >= 0.0).all() and (t <= 70.0).all()
    # Near the ceiling anchor, 600 mm off its axis, the lower lines would have to push.
    tensions, held = m.tensions(np.array([[600.0, 600.0, 1900.0]]))
    assert held.tolist() == [False]
    np.testing.assert_allclose(tensions[0, :3], [-4.176, -4.176, -3.071], atol=5e-4)


def test_cable_robot_without_a_load_has_no_tensions(machines):
    # A Maslow 4's sled lies on its sheet: no mass, no tension limits, every tension 0.
    m = pkmkit.Machine.load(str(machines / "maslow4.toml"))
    joints, status = m.inverse(np.array([[1461.9, 1033.073, 0.0]]))
    assert status.tolist() == ["ok"]
    np.testing.assert_allclose(joints[0, 0], 1661.593459, atol=1e-6)
    with pytest.raises(ValueError, match="has no cable tensions to list"):
        m.tensions(np.array([[1461.9, 1033.073, 0.0]]))


def test_plotter_tensions_equal_pkm_ik(machines, pkm_binary):
    # The two-cable plotter's balance through the same call: what `pkm ik --json` prints.
    m = pkmkit.Machine.load(str(machines / "maslow-frame.toml"))
    tensions, held = m.tensions(np.array([[1489.2, -1072.6, 5.0]]))
    result = subprocess.run([pkm_binary, "ik", "-m", str(machines / "maslow-frame.toml"),
                             "--json", "1489.2", "-1072.6", "5"],
                            capture_output=True, text=True, check=True)
    assert held.tolist() == [True]
    assert tensions[0].tolist() == json.loads(result.stdout)["cables"]["tension_N"]
