#!/usr/bin/env python3
"""Gathers the fuzz targets' seed corpora into OUT/<target>/: small files of the project's own
tests and examples, the head of every program of the real G-code corpus (when present), each
cut to its first lines so that one seed stays small, and LinuxCNC's sample configurations (when
installed), each INI followed by the files beside it that it names (fuzz/linuxcnc_ini.cpp's
`#FILE name` parts), and firmware configurations, each after its target's selector byte. Usage: make_seeds.py SOURCE_DIR CORPUS OUT [LINUXCNC_SAMPLES]"""
import hashlib
import re
import pathlib
import shutil
import sys

MAX_LINES = 300      # lines kept of a long G-code program
MAX_BYTES = 16384    # bytes kept of any seed

# Programs of the bad-input classes (tests/test_gcode_bad_input.cpp), as starting points.
BAD_INPUTS = [
    "G4294967296 X5\nM2\n", "G0 X[EXP[1000]]\nM2\n", "T4294967297\nM2\n",
    "o1 repeat [10**300]\nG0 X1\no1 endrepeat\nM2\n", "o1 while [1]\no1 endwhile\nM2\n",
    "o1 sub\no1 call\no1 endsub\no1 call\nM2\n", "G1 X1e-05 F100\nM2\n",
    "G0 X" + "-" * 200 + "1\nM2\n", "G0 X" + "[" * 200 + "1" + "]" * 200 + "\nM2\n",
    "o1 while [0]\no1 endwhileXYZ\nM2\n", "#<a>=1 #2=#<a> G0 X#2 Y[#<a>*2]\nM2\n",
    "G21 G0 Z5\nG83 X1 Z-10 R1 Q2 F100\nG91 G81 X1 Z-1 R1 L3\nG80\nM2\n",
    "G21 G0 X0 Y0\nG41.1 D2\nG1 X10 F100\nG2 X20 Y0 I5\nG40\nG1 X30\nM2\n",
]
BAD_MACHINES = ["a" + ".a" * 100 + " = 1\n", "x = " + "[" * 100 + "]" * 100 + "\n"]
# The firmware target's selector byte is a target's index in pkm::firmware::targets().
FIRMWARE_TARGETS = ["fluidnc", "klipper", "rrf", "grblhal", "marlin"]


def write(directory: pathlib.Path, data: bytes) -> None:
    data = data[:MAX_BYTES]
    directory.mkdir(parents=True, exist_ok=True)
    (directory / hashlib.sha1(data).hexdigest()).write_bytes(data)


def head(path: pathlib.Path) -> bytes:
    with path.open("rb") as f:
        return b"".join(line for _, line in zip(range(MAX_LINES), f))


def linuxcnc_config(ini: pathlib.Path) -> bytes:
    """The INI, then each file beside it that it names (#INCLUDE, HALFILE, ...), as the target's
    `#FILE name` parts, while the whole stays under MAX_BYTES; '/' in names is the target's '_'."""
    text = ini.read_bytes()
    seed = text
    names = re.findall(rb"[A-Za-z0-9_.-]+\.(?:hal|inc|tcl|tbl)\b", text)
    for name in dict.fromkeys(names):
        beside = ini.parent / name.decode()
        if beside.is_file() and len(seed) + beside.stat().st_size < MAX_BYTES:
            seed += b"\n#FILE " + name + b"\n" + beside.read_bytes()
    return seed


def firmware_configs(source: pathlib.Path):
    """(target's index, text) of every firmware file of tests/data/firmware (TARGET-NAME.EXT,
    exports of example machines) and every raw string of tests/test_firmware_TARGET.cpp (the
    users' configurations the tests read)."""
    for index, target in enumerate(FIRMWARE_TARGETS):
        for path in sorted(source.glob(f"tests/data/firmware/{target}-*")):
            yield index, path.read_bytes()
        test = source / f"tests/test_firmware_{target}.cpp"
        if test.is_file():
            for text in re.findall(rb'R"\((.*?)\)"', test.read_bytes(), re.DOTALL):
                yield index, text


def main() -> None:
    source, corpus, out = (pathlib.Path(a) for a in sys.argv[1:4])
    samples = pathlib.Path(sys.argv[4]) if len(sys.argv) > 4 else None
    shutil.rmtree(out, ignore_errors=True)
    gcode = [*source.glob("tests/gcode/*.ngc"), *source.glob("tests/data/*.ngc"),
             *source.glob("examples/jobs/*.ngc")]
    if (corpus / "SOURCES.md").is_file():
        gcode += [p for p in corpus.rglob("*") if p.is_file() and p.name != "SOURCES.md"]
    for path in gcode:
        write(out / "gcode_interpreter", head(path))
    for text in BAD_INPUTS:
        write(out / "gcode_interpreter", text.encode())
    for path in [*source.glob("tests/data/*.ngc"), *source.glob("examples/jobs/*.ngc")]:
        write(out / "joint_program", head(path))
    write(out / "joint_program", b"(tolerance 0.010000 mm)\nG21 G90 G94\nG1 X1000 Y1000 F600\nM2\n")
    for path in [*source.glob("examples/machines/*.toml"), *source.glob("tests/data/*.toml")]:
        write(out / "machine_file", path.read_bytes())
    for text in BAD_MACHINES:
        write(out / "machine_file", text.encode())
    for path in source.glob("tests/data/*.csv"):
        write(out / "calibration_csv", path.read_bytes())
    write(out / "calibration_csv", b"mark_a,mark_b,distance_mm\n1,2,100.5\n2,3,99\n")
    for path in source.glob("tests/data/*pattern*.json"):
        write(out / "calibration_pattern", path.read_bytes())
    write(out / "calibration_pattern", b'{"marks": [{"id": 1, "x": 1e6, "y": -0.0005}]}')
    for index, text in firmware_configs(source):
        write(out / "firmware_config", bytes([index]) + text)
    inis = [*source.glob("tests/data/linuxcnc/*/*.ini")]
    if samples is not None and samples.is_dir():
        inis += sorted(samples.rglob("*.ini"))
    for path in inis:
        write(out / "linuxcnc_ini", linuxcnc_config(path))


if __name__ == "__main__":
    main()
