"""Builds the pkmkit extension with the project's CMake (pyproject.toml; docs/python.md).

The extension is CMake's target `pkmkit` (python/CMakeLists.txt), configured for the Python
running this build, without the tests, benchmarks and LinuxCNC module, in setuptools' build_temp;
the built .so is copied where setuptools expects it. CMAKE_ARGS (space-separated) is passed to
the configure step, e.g. CMAKE_ARGS="-DCMAKE_CXX_COMPILER_LAUNCHER=ccache". PKMKIT_BUILD_DIR names
a build directory where the module is built already, to take it from there instead of building
it (what the pip test of ctest does with its own build, python/CMakeLists.txt).
"""
import os
import pathlib
import shutil
import subprocess
import sys

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

SOURCE_DIR = pathlib.Path(__file__).resolve().parent


class CMakeBuild(build_ext):
    def build_extension(self, ext):
        if os.environ.get("PKMKIT_BUILD_DIR"):
            build_dir = pathlib.Path(os.environ["PKMKIT_BUILD_DIR"]).resolve()
        else:
            build_dir = pathlib.Path(self.build_temp).resolve() / "cmake"
            self.configure(build_dir)
            subprocess.run(["cmake", "--build", str(build_dir), "--target", "pkmkit"], check=True)
        built = next((build_dir / "python").glob("pkmkit*.so"))
        target = pathlib.Path(self.get_ext_fullpath(ext.name))
        target.parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(built, target)

    @staticmethod
    def configure(build_dir):
        configure = [
            "cmake", "-S", str(SOURCE_DIR), "-B", str(build_dir), "-DCMAKE_BUILD_TYPE=Release",
            f"-DPython_EXECUTABLE={sys.executable}", "-DPKM_BUILD_PYTHON=ON",
            "-DPKM_BUILD_TESTS=OFF", "-DPKM_BUILD_BENCHMARKS=OFF", "-DPKM_BUILD_LINUXCNC=OFF",
            *os.environ.get("CMAKE_ARGS", "").split()
        ]
        if shutil.which("ninja"):
            configure.append("-GNinja")
        subprocess.run(configure, check=True)


setup(ext_modules=[Extension("pkmkit", sources=[])], cmdclass={"build_ext": CMakeBuild})
