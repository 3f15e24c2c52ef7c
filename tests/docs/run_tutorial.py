#!/usr/bin/python3
"""Runs the README's tutorial as a reader would, and checks what it promises.

    run_tutorial.py SOURCE_DIR BILLIARD_BINARY

README.md marks the tutorial with HTML comments, so that the test and the text cannot drift:
  <!-- tutorial:file NAME -->      the fenced block after it is saved as NAME;
  <!-- tutorial:run -->            every line of the fenced block after it is a command;
  <!-- tutorial:produces A B ... --> these files must exist, non-empty, once the commands ran.
Everything runs in a fresh folder, in the README's order, with the binary's folder first on
PATH and `scripts/` linked to the source tree's; each command must exit with status 0.
"""
import os
import re
import shutil
import subprocess
import sys
import tempfile

MARK = re.compile(r"<!-- tutorial:(\w+)(?: ([^\n]*?))? -->\n(?:```\w*\n(.*?)```)?", re.S)


def steps(readme):
    """The tutorial's steps in order: (kind, argument, block)."""
    found = [(m.group(1), (m.group(2) or "").strip(), m.group(3)) for m in MARK.finditer(readme)]
    kinds = {k for k, _, _ in found}
    if not {"file", "run", "produces"} <= kinds:
        raise SystemExit(f"README.md: the tutorial's markers are missing (found {sorted(kinds)})")
    return found


def main():
    source, binary = sys.argv[1], os.path.abspath(sys.argv[2])
    readme = open(os.path.join(source, "README.md"), encoding="utf-8").read()
    work = tempfile.mkdtemp(prefix=f"billiards-tutorial-{os.getpid()}-")
    failures = []
    try:
        os.symlink(os.path.join(os.path.abspath(source), "scripts"), os.path.join(work, "scripts"))
        env = dict(os.environ, PATH=os.path.dirname(binary) + os.pathsep + os.environ["PATH"])
        for kind, arg, block in steps(readme):
            if kind == "file":
                with open(os.path.join(work, arg), "w") as f:
                    f.write(block)
            elif kind == "run":
                for command in block.strip().splitlines():
                    r = subprocess.run(["bash", "-c", command], cwd=work, env=env, capture_output=True, text=True)
                    print(f"$ {command}  -> exit {r.returncode}")
                    if r.returncode != 0:
                        failures.append(f"'{command}' exited with {r.returncode}: {r.stderr.strip()[-500:]}")
            elif kind == "produces":
                for name in arg.split():
                    path = os.path.join(work, name)
                    if not (os.path.isfile(path) and os.path.getsize(path) > 0):
                        failures.append(f"'{name}' was not produced")
    finally:
        shutil.rmtree(work, ignore_errors=True)
    for f in failures:
        print("FAILED:", f)
    sys.exit(1 if failures else 0)


if __name__ == "__main__":
    main()
