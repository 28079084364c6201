"""Builds the horizon Python module with CMake for `pip install .` (pyproject.toml).

The module is the CMake target horizon_python; this only runs CMake in build/pip (or
$HORIZON_BUILD_DIR) for the interpreter pip runs, and copies the result.
"""
import glob
import os
import shutil
import subprocess
import sys

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

ROOT = os.path.abspath(os.path.dirname(__file__))


class CMakeBuild(build_ext):
    def build_extension(self, ext):
        build = os.environ.get("HORIZON_BUILD_DIR", os.path.join(ROOT, "build", "pip"))
        subprocess.check_call(["cmake", "-S", ROOT, "-B", build, "-G", "Ninja", "-DCMAKE_BUILD_TYPE=Release",
                               "-DPython_EXECUTABLE=" + sys.executable])
        jobs = os.environ.get("HORIZON_JOBS", str(os.cpu_count() or 2))
        subprocess.check_call(["cmake", "--build", build, "--target", "horizon_python", "-j", jobs])
        built = glob.glob(os.path.join(build, "python", "horizon", "_core*.so"))
        if not built:
            raise RuntimeError("CMake did not build the module (is pybind11-dev installed? make deps)")
        dest = self.get_ext_fullpath(ext.name)
        os.makedirs(os.path.dirname(dest), exist_ok=True)
        shutil.copyfile(built[0], dest)


setup(
    packages=["horizon"],
    package_dir={"": "python"},
    ext_modules=[Extension("horizon._core", sources=[])],
    cmdclass={"build_ext": CMakeBuild},
)
