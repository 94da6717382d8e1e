"""`pip install .`: the Python module `vrv`, the `vrv` program and its image module, built by CMake.

Installed as the package <site>/vrv/: the module (vrv.cpython-*.so, imported by __init__.py), the
program `vrv`, and beside them the image module and the plot script, where both look first
(lib/util/install_dirs.h: their own directory), whatever the scheme (--prefix, --target, --user).
The command `vrv` in the scheme's bin/ runs that program (vrv/__main__.py; also `python3 -m vrv`).

The build is CMake's, lean (-DVRV_BUILD_TESTS=OFF -DVRV_BUILD_BENCHMARKS=OFF) in build-pip/, for
the Python that runs pip.  VRV_PIP_BUILD_DIR=<an existing configured build tree> builds the three
targets there instead (nothing when they are built: CI's tests install what CI already built).
"""
import os
import re
import shutil
import subprocess
import sys
import sysconfig
from pathlib import Path

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

SOURCE = Path(__file__).resolve().parent
EXISTING = os.environ.get("VRV_PIP_BUILD_DIR", "")
BASE = Path(EXISTING).resolve() / "pip" if EXISTING else SOURCE / "build-pip"
BASE.mkdir(parents=True, exist_ok=True)
IMAGE_MODULE = "libvrv_image.so"


def version():
    cmake = (SOURCE / "CMakeLists.txt").read_text()
    return re.search(r"project\(vrv VERSION ([0-9.]+)", cmake).group(1)


def run(*command):
    print("+", " ".join(map(str, command)), flush=True)
    subprocess.run([str(c) for c in command], check=True)


def cmake_build_dir():
    """The build tree: VRV_PIP_BUILD_DIR's (it must be configured), else a fresh lean one."""
    if EXISTING:
        tree = Path(EXISTING).resolve()
        if not (tree / "CMakeCache.txt").is_file():
            sys.exit(f"VRV_PIP_BUILD_DIR: {tree} is not a configured CMake build tree (no CMakeCache.txt)")
        return tree
    tree = BASE / "cmake"
    run("cmake", "-S", SOURCE, "-B", tree, "-DCMAKE_BUILD_TYPE=Release", "-DVRV_BUILD_TESTS=OFF",
        "-DVRV_BUILD_BENCHMARKS=OFF", f"-DPython3_EXECUTABLE={sys.executable}")
    return tree


def built_module(tree):
    """The tree's Python module, which must be built for the Python running pip."""
    suffix = sysconfig.get_config_var("EXT_SUFFIX")
    found = sorted((tree / "python").glob("vrv.*.so"))
    if not any(f.name == "vrv" + suffix for f in found):
        sys.exit(f"{tree}/python has {[f.name for f in found]}, not vrv{suffix} for "
                 f"{sys.executable} (configure it with -DPython3_EXECUTABLE={sys.executable})")
    return tree / "python" / ("vrv" + suffix)


class CMakeBuild(build_ext):
    def build_extension(self, ext):
        tree = cmake_build_dir()
        jobs = os.environ.get("CMAKE_BUILD_PARALLEL_LEVEL", str(os.cpu_count() or 1))
        run("cmake", "--build", tree, "--target", "vrv", "vrv_image", "vrv_python", "--parallel", jobs)
        package = Path(self.get_ext_fullpath(ext.name)).parent
        package.mkdir(parents=True, exist_ok=True)
        shutil.copy2(built_module(tree), self.get_ext_fullpath(ext.name))
        for f in (tree / "vrv", tree / IMAGE_MODULE, SOURCE / "studies" / "engine" / "plot_study.py"):
            shutil.copy2(f, package / f.name)


setup(
    version=version(),
    packages=["vrv"],
    package_dir={"vrv": "studies/python/package"},
    ext_modules=[Extension("vrv.vrv", sources=[])],
    cmdclass={"build_ext": CMakeBuild},
    options={"build": {"build_base": str(BASE / "setuptools")},
             "egg_info": {"egg_base": str(BASE)}},
    zip_safe=False,
)
