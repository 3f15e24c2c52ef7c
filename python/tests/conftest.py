"""Fixtures shared by the tests of the Python package billiardkit: the source tree and the
`billiard` program.

ctest (tests/package/check_python_package.py) installs billiardkit into a fresh venv and runs these
tests there with BILLIARDS_BINARY and BILLIARDS_SOURCE_DIR set; by hand, against the CMake build:
PYTHONPATH=build/python BILLIARDS_BINARY=build/cli/billiard /usr/bin/python3 -m pytest python/tests
"""
import json
import os
import pathlib
import subprocess

import pytest

SOURCE = pathlib.Path(os.environ.get("BILLIARDS_SOURCE_DIR", pathlib.Path(__file__).resolve().parents[2]))
BINARY = os.environ.get("BILLIARDS_BINARY", str(SOURCE / "build" / "cli" / "billiard"))


@pytest.fixture
def source():
    return SOURCE


def billiard(*args, cwd=None):
    """Runs `billiard ARGS` and returns its stdout; fails the test on a non-zero exit."""
    done = subprocess.run([BINARY, *map(str, args)], cwd=cwd or SOURCE, capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    return done.stdout


def billiard_json(*args):
    return json.loads(billiard(*args, "--json"))
