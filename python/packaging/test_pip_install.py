"""pip's offline install of pkmkit into a fresh venv (docs/python.md, "Installing with pip").

    test_pip_install.py SOURCE_DIR BUILD_DIR WORK_DIR

Makes a venv with --system-site-packages in WORK_DIR, runs `pip install --no-build-isolation
--no-index` in it on a copy of SOURCE_DIR's packaging files (pyproject.toml, setup.py and the
readme: pip builds in the tree it is given, and the source tree stays clean) taking the module
BUILD_DIR built (PKMKIT_BUILD_DIR: configuring and compiling it again would take minutes), then
imports pkmkit in the venv, without PYTHONPATH, and checks that it is the installed one and that
it works.
"""
import os
import pathlib
import shutil
import subprocess
import sys

CHECK = """
import pathlib, sys, numpy as np, pkmkit
assert pathlib.Path(pkmkit.__file__).is_relative_to(sys.prefix), pkmkit.__file__
m = pkmkit.Machine.load(sys.argv[1])
joints, status = m.inverse(np.array([[34.0, -40.0]]))
assert status.tolist() == ["ok"] and round(joints[0, 0], 3) == 52.498, (joints, status)
samples, report = pkmkit.plan(m, sys.argv[2], period=0.01)
assert len(samples) == report["samples"] > 10 and samples.dtype.names[-1] == "j_right", report
print("pkmkit installed at", pkmkit.__file__)
"""


def main():
    source, build, work = (pathlib.Path(arg).resolve() for arg in sys.argv[1:4])
    shutil.rmtree(work, ignore_errors=True)
    venv = work / "venv"
    tree = work / "source"
    for name in ("pyproject.toml", "setup.py", "docs/python.md"):
        (tree / name).parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(source / name, tree / name)
    subprocess.run([sys.executable, "-m", "venv", "--system-site-packages", str(venv)], check=True)
    python = venv / "bin" / "python"
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    env["PKMKIT_BUILD_DIR"] = str(build)
    subprocess.run([str(python), "-m", "pip", "install", "-q", "--no-build-isolation", "--no-index", "--no-cache-dir",
                    str(tree)], check=True, env=env, cwd=work)
    del env["PKMKIT_BUILD_DIR"]
    subprocess.run([str(python), "-c", CHECK, str(source / "examples/machines/hektor.toml"),
                    str(source / "tests/data/hektor-job.ngc")],
                   check=True, env=env, cwd=work)


if __name__ == "__main__":
    main()
