"""pkmkit.plan and plan_chunks: the samples of `pkm plan` as structured arrays, bit for bit."""
import json
import subprocess

import numpy as np
import pytest

import pkmkit


def pkm_plan(pkm_binary, tmp_path, machine_file, job, *options):
    """`pkm plan -o OUT.npy --report R.json` of a job: (the samples as NumPy reads them, report)."""
    npy, report = tmp_path / "samples.npy", tmp_path / "report.json"
    subprocess.run([pkm_binary, "plan", "-m", str(machine_file), str(job), "-o", str(npy),
                    "--report", str(report), *options], capture_output=True, check=True)
    return np.load(npy), json.loads(report.read_text())


# (machine, job, pkm plan's options, pkmkit.plan's keywords): a cable plotter's job with an arc,
# the paper's sphere on its hexapod (orientation columns), a pen plotter (the pen column) placed
# by --origin.
CASES = [
    ("hektor.toml", "tests/data/hektor-job.ngc", ["--period", "0.01"], {"period": 0.01}),
    ("hexapod-bit.toml", "examples/jobs/sphere.ngc", ["--period", "0.004"], {"period": 0.004}),
    ("pen-plotter.toml", "tests/data/square.ngc", ["--origin", "700", "-650", "--jerk", "20000"],
     {"origin": [700, -650], "jerk": 20000.0}),
]


@pytest.mark.parametrize("name,job,options,keywords", CASES, ids=[c[0] for c in CASES])
def test_plan_equals_pkm_plan_npy_bit_for_bit(machines, pkm_binary, tmp_path, name, job, options,
                                              keywords):
    source = machines.parent.parent
    m = pkmkit.Machine.load(str(machines / name))
    samples, report = pkmkit.plan(m, str(source / job), **keywords)
    expected, expected_report = pkm_plan(pkm_binary, tmp_path, machines / name, source / job,
                                         *options)
    assert samples.dtype == expected.dtype  # the same names, all '<f8'
    assert len(samples) == len(expected) == report["samples"] > 10
    assert samples.tobytes() == expected.tobytes()
    assert report == expected_report


def test_plan_columns_and_report_values(machines, test_data):
    # Hektor's job at 10 ms: t steps by the period (the last sample is the job's end), the joints are the lengths from the anchors
    # (0, 0) and (100, 0) to the pen, and the report's ranges are the samples'.
    m = pkmkit.Machine.load(str(machines / "hektor.toml"))
    samples, report = pkmkit.plan(m, str(test_data / "hektor-job.ngc"), period=0.01)
    assert samples.dtype.names == ("t", "line", "x", "y", "z", "j_left", "j_right")
    steps = np.diff(samples["t"])
    np.testing.assert_allclose(steps[:-1], 0.01, atol=1e-9)
    assert 0 < steps[-1] <= 0.01 + 1e-9
    np.testing.assert_allclose(samples["j_left"], np.hypot(samples["x"], samples["y"]), atol=1e-9)
    np.testing.assert_allclose(samples["j_right"], np.hypot(100 - samples["x"], samples["y"]),
                               atol=1e-9)
    assert set(samples["line"].astype(int)) == {0, 3, 4, 5, 6}  # 0: the start, before a move
    left = report["joints"][0]
    assert (left["name"], left["unit"]) == ("left", "mm")
    assert left["min"] == samples["j_left"].min() and left["max"] == samples["j_left"].max()
    assert report["period_s"] == 0.01 and report["estimate"] is False


def test_plan_chunks_concatenate_to_the_whole(machines, jobs):
    m = pkmkit.Machine.load(str(machines / "hexapod-bit.toml"))
    whole, report = pkmkit.plan(m, str(jobs / "sphere.ngc"), period=0.004)
    chunks = pkmkit.plan_chunks(m, str(jobs / "sphere.ngc"), period=0.004, chunk=1000)
    assert chunks.report is None
    parts = list(chunks)
    assert [len(p) for p in parts[:-1]] == [1000] * (len(parts) - 1)
    assert 1 <= len(parts[-1]) <= 1000 and len(parts) == -(-len(whole) // 1000)
    assert np.concatenate(parts).tobytes() == whole.tobytes()
    assert chunks.report == report
    assert list(chunks) == []  # exhausted


def test_plan_chunks_shared_by_four_threads(machines, jobs):
    # Four threads taking chunks from one iterator deadlocked 6 of 6 runs (issue 26: the GIL
    # against the iterator's mutex). Every chunk is taken once, by one thread or another.
    import threading
    m = pkmkit.Machine.load(str(machines / "hexapod-bit.toml"))
    whole, _ = pkmkit.plan(m, str(jobs / "sphere.ngc"), period=0.004)
    chunks = pkmkit.plan_chunks(m, str(jobs / "sphere.ngc"), period=0.004, chunk=20)
    taken = []

    def take():
        for part in chunks:
            taken.append(part)

    threads = [threading.Thread(target=take, daemon=True) for _ in range(4)]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join(timeout=30)
    assert not any(thread.is_alive() for thread in threads), "deadlocked"
    assert sum(len(part) for part in taken) == len(whole)
    ordered = np.sort(np.concatenate(taken), order="t")
    assert ordered.tobytes() == whole.tobytes()


def test_plan_chunks_left_early_stop_the_planner(machines, jobs):
    # One chunk of the sphere, then the iterator goes: its planner's thread must end (the test
    # would hang otherwise), and another plan runs as before.
    m = pkmkit.Machine.load(str(machines / "hexapod-bit.toml"))
    chunks = pkmkit.plan_chunks(m, str(jobs / "sphere.ngc"), chunk=10)
    first = next(chunks)
    assert len(first) == 10 and first["t"][0] == 0.0
    del chunks
    again = next(pkmkit.plan_chunks(m, str(jobs / "sphere.ngc"), chunk=10))
    assert again.tobytes() == first.tobytes()


def test_plan_of_a_move_out_of_reach_raises_plan_error(machines, test_data, pkm_binary):
    m = pkmkit.Machine.load(str(machines / "hexapod-bit.toml"))
    job = test_data / "hexapod-out-of-reach.ngc"
    with pytest.raises(pkmkit.PlanError) as raised:
        pkmkit.plan(m, str(job))
    assert raised.value.line == 3 and str(raised.value).startswith(f"{job}:3: ")
    assert "\n  hint: the job spans" in str(raised.value)  # where the job would fit
    cli = subprocess.run([pkm_binary, "plan", "-m", str(machines / "hexapod-bit.toml"), str(job)],
                         capture_output=True, text=True)
    assert cli.returncode != 0 and str(raised.value) in cli.stderr
    with pytest.raises(pkmkit.PlanError):  # the same from the chunks, when they reach it
        list(pkmkit.plan_chunks(m, str(job)))


def test_plan_of_a_bad_program_raises_gcode_error(machines, tmp_path):
    job = tmp_path / "bad.ngc"
    job.write_text("G21 G90\nG1 X10 Y-40 F600\nG1 X$ Y-30\nM2\n")
    m = pkmkit.Machine.load(str(machines / "hektor.toml"))
    with pytest.raises(pkmkit.GcodeError) as raised:
        pkmkit.plan(m, str(job))
    assert (raised.value.file, raised.value.line) == (str(job), 3)
    assert raised.value.column > 0 and isinstance(raised.value, ValueError)


def test_plan_bound_and_arguments(machines, test_data):
    m = pkmkit.Machine.load(str(machines / "hektor.toml"))
    job = str(test_data / "hektor-job.ngc")
    with pytest.raises(pkmkit.PlanError, match="would pass 100 samples"):
        pkmkit.plan(m, job, max_samples=100)
    # pkm plan's range and default (--max-samples 1 to 1e15, default 50000000); 0: no bound.
    for outside in (-1, 10**15 + 1):
        with pytest.raises(ValueError, match=r"max_samples must lie within \[0, 1e15\]"):
            pkmkit.plan(m, job, max_samples=outside)
    assert "max_samples: int = 50000000" in pkmkit.plan.__doc__
    with pytest.raises(ValueError, match="period"):
        pkmkit.plan(m, job, period=0.0)
    with pytest.raises(ValueError, match="attitude"):
        pkmkit.plan(m, job, attitude="spherical")
    with pytest.raises(ValueError, match="start must have 2 values"):
        pkmkit.plan(m, job, start=np.zeros(3))


def test_estimate_equals_pkm_plan_estimate(machines, jobs, pkm_binary, tmp_path):
    machine_file, job = machines / "hexapod-bit.toml", jobs / "sphere.ngc"
    report_file = tmp_path / "estimate.json"
    subprocess.run([pkm_binary, "plan", "-m", str(machine_file), str(job), "--estimate",
                    "--period", "0.004", "--report", str(report_file)], capture_output=True,
                   check=True)
    m = pkmkit.Machine.load(str(machine_file))
    estimate = pkmkit.estimate(m, str(job), period=0.004)
    assert estimate == json.loads(report_file.read_text())
    assert estimate["estimate"] is True and estimate["joints"][0]["peak_acceleration"] is None
    _, report = pkmkit.plan(m, str(job), period=0.004)
    assert estimate["samples"] == report["samples"]  # the count is exact
