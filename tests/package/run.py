"""What the package checks share: running a command and failing with its output."""
import subprocess
import sys


def sh(*args, cwd=None, env=None):
    """Runs ARGS and returns its stdout; exits with the command and its output if it fails."""
    done = subprocess.run([str(a) for a in args], cwd=cwd, env=env, capture_output=True, text=True)
    if done.returncode != 0:
        sys.exit(f"FAILED: {' '.join(map(str, args))}\n{done.stdout}\n{done.stderr}")
    return done.stdout


def check(condition, message):
    if not condition:
        sys.exit(f"FAILED: {message}")
