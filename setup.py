"""Builds billiardkit._core, the C++ core of the package, with CMake for the Python running this
(pyproject.toml has the rest).  BILLIARDKIT_CMAKE_BUILD_DIR reuses an existing CMake build of this
source tree (its target billiards_python is built there, for the Python it was configured with);
otherwise a Release build is configured in setuptools' build_temp.  CMAKE_ARGS adds to its
configuration."""
import os
import pathlib
import re
import shlex
import shutil
import subprocess
import sys

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

ROOT = pathlib.Path(__file__).resolve().parent


def version():
    text = (ROOT / "CMakeLists.txt").read_text()
    return re.search(r"project\(billiards\b[^)]*\bVERSION\s+([0-9.]+)", text).group(1)


class CMakeBuild(build_ext):
    def build_extension(self, ext):
        reuse = os.environ.get("BILLIARDKIT_CMAKE_BUILD_DIR")
        build = pathlib.Path(reuse or pathlib.Path(self.build_temp).resolve() / "cmake")
        if not reuse:
            args = ["-DCMAKE_BUILD_TYPE=Release", f"-DPython3_EXECUTABLE={sys.executable}", "-DBUILD_TESTING=OFF",
                    "-DBILLIARDS_MPI=OFF", *shlex.split(os.environ.get("CMAKE_ARGS", ""))]
            if shutil.which("ninja"):
                args += ["-G", "Ninja"]
            if shutil.which("ccache"):
                args.append("-DCMAKE_CXX_COMPILER_LAUNCHER=ccache")
            subprocess.check_call(["cmake", "-S", str(ROOT), "-B", str(build), *args])
        subprocess.check_call(["cmake", "--build", str(build), "--target", "billiards_python",
                               "-j", str(os.cpu_count() or 1)])
        built = build / "python" / "billiardkit" / os.path.basename(self.get_ext_filename("_core"))
        if not built.exists():
            sys.exit(f"setup.py: {built} not found: the CMake build in {build} is for another Python "
                     f"(this is {sys.executable})")
        target = pathlib.Path(self.get_ext_fullpath(ext.name))
        target.parent.mkdir(parents=True, exist_ok=True)
        shutil.copy2(built, target)


setup(version=version(), ext_modules=[Extension("billiardkit._core", sources=[])], cmdclass={"build_ext": CMakeBuild})
