"""Fixtures of the pkmkit tests: the example machines and the pkm binary of the same build.

ctest sets PYTHONPATH (the built module), PKM_BINARY and PKM_SOURCE_DIR (python/CMakeLists.txt).
"""
import os
import pathlib

import pytest

SOURCE_DIR = pathlib.Path(
    os.environ.get("PKM_SOURCE_DIR", pathlib.Path(__file__).resolve().parents[2]))
MACHINES = SOURCE_DIR / "examples" / "machines"


@pytest.fixture
def machines():
    return MACHINES


@pytest.fixture
def pkm_binary():
    binary = os.environ.get("PKM_BINARY", str(SOURCE_DIR / "build/release/apps/pkm/pkm"))
    if not os.access(binary, os.X_OK):
        pytest.fail(f"no pkm binary at {binary} (set PKM_BINARY)")
    return binary


@pytest.fixture
def jobs():
    return SOURCE_DIR / "examples" / "jobs"


@pytest.fixture
def test_data():
    return SOURCE_DIR / "tests" / "data"
