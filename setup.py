"""Builds the extension module `nsmodal` with CMake, for pip (see pyproject.toml).

The metadata is in pyproject.toml; this file adds what it cannot say:
the version, read from CMakeLists.txt (one version for the library, the command
and the module), and a build_ext that configures this CMake project with the
tests and benchmarks off, builds the target nsmodal_python, and copies the
module where setuptools packs it.

Environment:
  NSMODAL_CMAKE_ARGS          extra CMake options, split on spaces (e.g. -DNSMODAL_WERROR=ON)
  CMAKE_BUILD_PARALLEL_LEVEL  build jobs (default: every core)
"""
import glob
import os
import re
import shutil
import subprocess
import sys
import sysconfig

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

ROOT = os.path.dirname(os.path.abspath(__file__))
TARGET = "nsmodal_python"  # python/CMakeLists.txt: its OUTPUT_NAME is nsmodal


def cmake_project_version():
    with open(os.path.join(ROOT, "CMakeLists.txt"), encoding="utf-8") as f:
        match = re.search(r"project\(\s*nsmodal\s+VERSION\s+([0-9][0-9.]*)", f.read())
    if match is None:
        sys.exit("setup.py: no project(nsmodal VERSION x.y.z) in CMakeLists.txt")
    return match.group(1)


class CMakeExtension(Extension):
    def __init__(self, name):
        super().__init__(name, sources=[])


class CMakeBuild(build_ext):
    def build_extension(self, ext):
        if shutil.which("cmake") is None:
            raise RuntimeError("nsmodal: cmake is not on PATH (bash scripts/setup.sh installs it and the libraries)")
        build_dir = os.path.abspath(os.path.join(self.build_temp, "cmake"))
        os.makedirs(build_dir, exist_ok=True)
        configure = [
            "cmake", "-S", ROOT, "-B", build_dir,
            "-DCMAKE_BUILD_TYPE=Release",
            "-DNSMODAL_BUILD_PYTHON=ON",
            "-DNSMODAL_BUILD_TESTS=OFF",
            "-DNSMODAL_BUILD_BENCH=OFF",
            # The interpreter pip runs (a venv's): the module is built for it.
            f"-DPython_EXECUTABLE={sys.executable}",
        ] + os.environ.get("NSMODAL_CMAKE_ARGS", "").split()
        build = ["cmake", "--build", build_dir, "--target", TARGET]
        if "CMAKE_BUILD_PARALLEL_LEVEL" not in os.environ:
            build += ["-j", str(os.cpu_count() or 1)]
        subprocess.run(configure, check=True)
        subprocess.run(build, check=True)

        suffix = sysconfig.get_config_var("EXT_SUFFIX")
        built = glob.glob(os.path.join(build_dir, "python", "nsmodal", "_nsmodal" + suffix))
        if len(built) != 1:
            found = glob.glob(os.path.join(build_dir, "python", "nsmodal", "*"))
            raise RuntimeError(f"nsmodal: expected python/nsmodal/_nsmodal{suffix} in {build_dir}, found {found}")
        destination = self.get_ext_fullpath(ext.name)
        os.makedirs(os.path.dirname(destination), exist_ok=True)
        shutil.copyfile(built[0], destination)


setup(
    version=cmake_project_version(),
    # The package nsmodal (python/nsmodal: __init__.py, the stubs and py.typed)
    # with its extension nsmodal._nsmodal; no discovery among the C++ folders.
    # Said here rather than in pyproject.toml's [tool.setuptools], which
    # setuptools 66 still calls beta and warns about.
    packages=["nsmodal"],
    package_dir={"nsmodal": "python/nsmodal"},
    package_data={"nsmodal": ["__init__.pyi", "py.typed"]},
    py_modules=[],
    ext_modules=[CMakeExtension("nsmodal._nsmodal")],
    cmdclass={"build_ext": CMakeBuild},
    # Beside CMake's own build/ tree, not inside the CMake cache's directory.
    options={"build": {"build_base": os.path.join("build", "pip")}},
    zip_safe=False,
)
