"""pkmkit.post and pkmkit.verify: the files and reports of `pkm post` and `pkm verify`."""
import json
import subprocess

import pytest

import pkmkit


def run_pkm(pkm_binary, *arguments, check=True):
    return subprocess.run([pkm_binary, *map(str, arguments)], capture_output=True, text=True,
                          check=check)


@pytest.mark.parametrize("dialect,tolerance", [("linuxcnc", 0.01), ("mach3", 0.05)])
def test_post_writes_pkm_posts_file_and_report(machines, test_data, pkm_binary, tmp_path, dialect,
                                               tolerance):
    machine_file, job = machines / "hektor.toml", test_data / "hektor-job.ngc"
    cli_out, cli_report = tmp_path / "cli.ngc", tmp_path / "cli.json"
    run_pkm(pkm_binary, "post", "-m", machine_file, job, "-o", cli_out, "--report", cli_report,
            "--dialect", dialect, "--tolerance", tolerance)
    out = tmp_path / "py.ngc"
    report = pkmkit.post(pkmkit.Machine.load(str(machine_file)), str(job), str(out),
                         dialect=dialect, tolerance=tolerance)
    assert out.read_bytes() == cli_out.read_bytes()
    expected = json.loads(cli_report.read_text())
    assert report["output"] == str(out) and expected["output"] == str(cli_out)
    assert {**report, "output": None} == {**expected, "output": None}
    assert report["blocks"] > report["moves"] >= 4 and report["max_deviation_mm"] <= tolerance


def test_verify_gives_pkm_verifys_report(machines, test_data, pkm_binary, tmp_path):
    machine_file, job = machines / "hektor.toml", test_data / "hektor-job.ngc"
    m = pkmkit.Machine.load(str(machine_file))
    joints = tmp_path / "joints.ngc"
    pkmkit.post(m, str(job), str(joints), tolerance=0.01)
    report = pkmkit.verify(m, str(joints), against=str(job))  # the header's tolerance
    cli_report = tmp_path / "cli.json"
    run_pkm(pkm_binary, "verify", "-m", machine_file, joints, "--against", job, "--report",
            cli_report)
    assert report == json.loads(cli_report.read_text())
    assert report["passed"] is True and report["tolerance_mm"] == 0.01
    assert report["coverage"]["complete"] is True
    # Against a tighter tolerance than it was written for it fails, as pkm verify does (which
    # exits non-zero but writes the same report).
    tight = pkmkit.verify(m, str(joints), against=str(job), tolerance=0.0001)
    failed = run_pkm(pkm_binary, "verify", "-m", machine_file, joints, "--against", job,
                     "--tolerance", "0.0001", "--report", cli_report, check=False)
    assert failed.returncode != 0 and tight["passed"] is False
    assert tight == json.loads(cli_report.read_text())
    assert tight["violations"]["deviation"]["count"] > 0


def test_post_and_verify_errors(machines, test_data, pkm_binary, tmp_path):
    hexapod = pkmkit.Machine.load(str(machines / "hexapod-bit.toml"))
    job = test_data / "hexapod-out-of-reach.ngc"
    with pytest.raises(pkmkit.PostError, match=r"hexapod-out-of-reach.ngc:3: ") as raised:
        pkmkit.post(hexapod, str(job), str(tmp_path / "o.ngc"))
    cli = subprocess.run([pkm_binary, "post", "-m", str(machines / "hexapod-bit.toml"), str(job),
                          "-o", str(tmp_path / "cli.ngc")], capture_output=True, text=True)
    assert cli.returncode != 0 and cli.stderr == f"pkm: error: {raised.value}\n"
    assert "\n  hint: " in str(raised.value)
    assert not (tmp_path / "o.ngc").exists()  # nothing left behind
    m = pkmkit.Machine.load(str(machines / "hektor.toml"))
    with pytest.raises(ValueError, match="unknown dialect"):
        pkmkit.post(m, str(test_data / "hektor-job.ngc"), str(tmp_path / "o.ngc"), dialect="fanuc")
    # An arc of a million turns: refused from its estimate before any block, as pkm post.
    with pytest.raises(pkmkit.PostError, match=r"helix-million-turns.ngc:3: .* would pass the "
                       r"bound of 10000000 blocks\. .*raise max_blocks$"):
        pkmkit.post(m, str(test_data / "helix-million-turns.ngc"), str(tmp_path / "o.ngc"),
                    origin=[10, 0])
    assert not (tmp_path / "o.ngc").exists()
    with pytest.raises(ValueError, match="max_blocks must be >= 0"):
        pkmkit.post(m, str(test_data / "hektor-job.ngc"), str(tmp_path / "o.ngc"), max_blocks=-1)
    bare = tmp_path / "bare.ngc"
    bare.write_text("G1 X52 Y77 F600\nM2\n")
    with pytest.raises(ValueError, match="no tolerance to verify against"):
        pkmkit.verify(m, str(bare), against=str(test_data / "hektor-job.ngc"))


def test_post_span_moves_false_is_no_span_moves(machines, pkm_binary, tmp_path):
    # 50 collinear moves of 0.2 mm: spanned by a few blocks, or at least one block each.
    machine_file, job = machines / "hektor.toml", tmp_path / "tiny.ngc"
    job.write_text("G21 G90 G0 X40 Y-50\nG1 F600\n" +
                   "".join("G1 X%.1f Y-50\n" % (40 + 0.2 * k) for k in range(1, 51)) + "M2\n")
    m = pkmkit.Machine.load(str(machine_file))
    cli_out, out = tmp_path / "cli.ngc", tmp_path / "py.ngc"
    run_pkm(pkm_binary, "post", "-m", machine_file, job, "-o", cli_out, "--no-span-moves")
    per_move = pkmkit.post(m, str(job), str(out), span_moves=False)
    assert out.read_bytes() == cli_out.read_bytes()
    assert per_move["moves"] == 51 and per_move["blocks"] >= 51
    spanned = pkmkit.post(m, str(job), str(out))
    assert spanned["blocks"] * 5 < per_move["blocks"]


def test_post_never_writes_over_its_inputs(machines, pkm_binary, tmp_path):
    # pkmkit.post once overwrote the job or the machine file given as its output (issue 26);
    # pkm refuses both, and a subroutine file the job calls, as the Python call now does.
    machine_file = tmp_path / "hektor.toml"
    machine_file.write_text((machines / "hektor.toml").read_text())
    m = pkmkit.Machine.load(str(machine_file))
    square = tmp_path / "square.ngc"
    square.write_text("o<square> sub\nG1 X40 Y-60 F600\nG1 X60 Y-60\no<square> endsub\nM2\n")
    job = tmp_path / "job.ngc"
    job.write_text("G0 X50 Y-50\no<square> call\nM2\n")
    for output, what in [(job, "the job"), (machine_file, "the machine file"),
                         (square, "a subroutine file the job calls")]:
        before = output.read_text()
        with pytest.raises(ValueError, match=f"the output is the input file .* \\({what}\\)"):
            pkmkit.post(m, str(job), str(output))
        assert output.read_text() == before
        cli = run_pkm(pkm_binary, "post", "-m", machine_file, job, "-o", output, check=False)
        assert cli.returncode == 1 and f"({what})" in cli.stderr
        assert output.read_text() == before
    pkmkit.post(m, str(job), str(tmp_path / "joints.ngc"))
    assert "X" in (tmp_path / "joints.ngc").read_text() or "A" in (tmp_path / "joints.ngc").read_text()
