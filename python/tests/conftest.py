"""Fixtures shared by the tests of the Python package billiardkit: the source tree and the
`billiard` program.

ctest (tests/package/check_python_package.py) installs billiardkit into a fresh venv and runs these
tests there with BILLIARDS_BINARY and BILLIARDS_SOURCE_DIR set; by hand, against the CMake build:
PYTHONPATH=build/python BILLIARDS_BINARY=build/cli/billiard /usr/bin/python3 -m pytest python/tests
"""
import json
import os
import pathlib
import signal
import subprocess
import sys
import time

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


def interrupted(script):
    """Runs `script` in a fresh Python; once it prints 'started', sends it SIGINT and returns its
    exit status and the rest of its output (the script reports a KeyboardInterrupt itself)."""
    proc = subprocess.Popen([sys.executable, "-c", script], stdout=subprocess.PIPE, text=True)
    assert proc.stdout.readline() == "started\n"
    time.sleep(0.5)
    proc.send_signal(signal.SIGINT)
    try:
        out, _ = proc.communicate(timeout=30)
    finally:
        proc.kill()
    return proc.returncode, out
