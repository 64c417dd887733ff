"""Build of the package warpchol for pip (pyproject.toml): the extension module
warpchol._warpchol is this project's CMake target warpchol_python, built in a CMake build
tree of the repository above and copied into the package.

    python3 -m pip install --no-build-isolation --no-index ./python

Environment:
  WARPCHOL_CMAKE_BUILD_DIR  an existing, configured build tree of the repository (build/;
                            a relative path is taken from the repository's root): its
                            warpchol_python target is brought up to date and taken, instead
                            of configuring and compiling the solver anew (minutes); it must
                            have been configured for this interpreter's version
  WARPCHOL_BUILD_BASE       where setuptools and the new CMake build tree go (default:
                            python/build, inside the source tree)
  CMAKE_BUILD_PARALLEL_LEVEL  parallel compile jobs (default: the machine's cores)
"""

import os
import re
import subprocess
import sys
import sysconfig
from pathlib import Path

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

HERE = Path(__file__).resolve().parent
REPOSITORY = HERE.parent
MODULE = "_warpchol" + sysconfig.get_config_var("EXT_SUFFIX")


def project_version():
    """The version of project(warpchol VERSION ...) in the top-level CMakeLists.txt."""
    text = (REPOSITORY / "CMakeLists.txt").read_text()
    return re.search(r"project\(warpchol VERSION ([0-9.]+)", text).group(1)


class CMakeBuild(build_ext):
    """Builds warpchol._warpchol with CMake and copies it where setuptools expects it."""

    def build_extension(self, extension):
        reused = os.environ.get("WARPCHOL_CMAKE_BUILD_DIR")
        if reused:
            # pip runs this file in python/: a relative path is the repository's (build).
            build_tree = (REPOSITORY / reused).resolve()
            if not (build_tree / "CMakeCache.txt").is_file():
                sys.exit(f"warpchol: WARPCHOL_CMAKE_BUILD_DIR={reused} is not a configured CMake build tree")
        else:
            build_tree = Path(self.build_temp).resolve() / "cmake"
            build_tree.mkdir(parents=True, exist_ok=True)
            self.run_command_line(["cmake", "-S", str(REPOSITORY), "-B", str(build_tree),
                                   "-DCMAKE_BUILD_TYPE=Release", f"-DPython3_EXECUTABLE={sys.executable}"])
        jobs = os.environ.get("CMAKE_BUILD_PARALLEL_LEVEL", str(os.cpu_count() or 1))
        self.run_command_line(["cmake", "--build", str(build_tree), "--target", "warpchol_python", "-j", jobs])
        built = build_tree / "python" / "warpchol" / MODULE
        if not built.is_file():
            found = sorted(p.name for p in (build_tree / "python" / "warpchol").glob("_warpchol*"))
            sys.exit(f"warpchol: no {MODULE} in {built.parent} (found {found or 'none'}): the build tree was "
                     f"configured for another Python than {sys.executable}")
        target = Path(self.get_ext_fullpath(extension.name))
        target.parent.mkdir(parents=True, exist_ok=True)
        self.copy_file(str(built), str(target))

    @staticmethod
    def run_command_line(command):
        print("warpchol:", " ".join(command), flush=True)
        subprocess.run(command, check=True)


build_base = os.environ.get("WARPCHOL_BUILD_BASE")
setup(
    version=project_version(),
    ext_modules=[Extension("warpchol._warpchol", sources=[])],
    cmdclass={"build_ext": CMakeBuild},
    options={"build": {"build_base": build_base}, "egg_info": {"egg_base": build_base}} if build_base else {},
)
