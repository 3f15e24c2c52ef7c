#!/usr/bin/python3
"""The Python package as a user gets it: `pip install --no-build-isolation .` into a fresh venv
(system site packages: Debian's numpy, matplotlib, pytest), python/tests run against that
installed package from outside the source tree; and a wheel from `python3 -m build --wheel
--no-isolation` installed into a second venv.  Both reuse BUILD_DIR's CMake build of the C++
core (BILLIARDKIT_CMAKE_BUILD_DIR), so nothing is compiled twice.

Usage: check_python_package.py SOURCE_DIR BUILD_DIR WORK_DIR
"""
import os
import pathlib
import shutil
import sys

from run import check, sh


def venv(path):
    sh(sys.executable, "-m", "venv", "--system-site-packages", path)
    return path / "bin" / "python"


def main():
    source, build, work = (pathlib.Path(a).resolve() for a in sys.argv[1:4])
    shutil.rmtree(work, ignore_errors=True)
    work.mkdir(parents=True)
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    env["BILLIARDKIT_CMAKE_BUILD_DIR"] = str(build)
    version = sh(env["BILLIARDS_BINARY"], "--version").split()[1]

    # pip install . : the whole test suite against the installed package.
    python = venv(work / "venv")
    sh(python, "-m", "pip", "install", "--no-build-isolation", "--no-index", "--quiet", source, cwd=work, env=env)
    where = sh(python, "-c", "import billiardkit; print(billiardkit.__file__)", cwd=work, env=env).strip()
    check(where.startswith(str(work / "venv")), f"billiardkit imported from {where}, not from the venv")
    print(sh(python, "-m", "pytest", "-q", "-p", "no:cacheprovider", source / "python" / "tests", cwd=work, env=env))

    # The wheel, into another venv.
    sh(sys.executable, "-m", "build", "--wheel", "--no-isolation", "--outdir", work / "dist", source, cwd=work, env=env)
    wheels = list((work / "dist").glob(f"billiardkit-{version}-*.whl"))
    check(len(wheels) == 1, f"expected one billiardkit-{version} wheel, found {wheels}")
    python = venv(work / "venv-wheel")
    sh(python, "-m", "pip", "install", "--no-index", "--quiet", wheels[0], cwd=work, env=env)
    smoke = (f"import billiardkit as bk, importlib.metadata as md, math\n"
             f"assert bk.__version__ == md.version('billiardkit') == {version!r}, bk.__version__\n"
             f"i = bk.load_shape({str(source / 'shapes' / 'circle.yaml')!r}).info()\n"
             f"assert abs(i['mean_free_path'] - math.pi * i['V'] / i['S']) < 1e-14\n"
             f"import billiardkit._core, os\n"
             f"assert os.path.isfile(os.path.join(os.path.dirname(bk.__file__), '__init__.pyi'))\n")
    sh(python, "-c", smoke, cwd=work, env=env)
    print(f"billiardkit {version}: pip install . and the wheel both install and work")


if __name__ == "__main__":
    main()
