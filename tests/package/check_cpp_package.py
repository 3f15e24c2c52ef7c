#!/usr/bin/python3
"""The C++ package as a user gets it: `cmake --install` into a fresh prefix, examples/cpp built
against it with find_package(billiards), its numbers equal to the installed `billiard`'s, and the
installed `billiard` finding its bundled scenes, shapes and plotting scripts under the prefix.

Usage: check_cpp_package.py SOURCE_DIR BUILD_DIR WORK_DIR
"""
import json
import os
import pathlib
import shutil
import sys

from run import check, sh


def main():
    source, build, work = (pathlib.Path(a).resolve() for a in sys.argv[1:4])
    shutil.rmtree(work, ignore_errors=True)
    prefix = work / "prefix"
    sh("cmake", "--install", build, "--prefix", prefix)

    # The installed program, run from outside the source tree, with nothing pointing at it.
    env = {k: v for k, v in os.environ.items() if not k.startswith("BILLIARDS_")}
    billiard = prefix / "bin" / "billiard"
    data = prefix / "share" / "billiards"
    version = sh(billiard, "--version", env=env).split()
    check(version[0] == "billiard" and len(version) == 2, f"billiard --version: {version}")
    help_text = sh(billiard, "bench", "speed-error", "--help", cwd=work, env=env)
    check(str(data / "scenes" / "clover-driven.yaml") in help_text, "the default scene is not the installed one")
    sh(billiard, "plot", data / "shapes" / "clover.yaml", "-o", work / "clover.png", cwd=work, env=env)
    check((work / "clover.png").stat().st_size > 1000, "plot wrote no PNG")

    # A user's project: examples/cpp against the prefix.
    cmake_args = ["-G", "Ninja", "-DCMAKE_BUILD_TYPE=Release", f"-DCMAKE_PREFIX_PATH={prefix}"]
    if shutil.which("ccache"):
        cmake_args.append("-DCMAKE_CXX_COMPILER_LAUNCHER=ccache")
    sh("cmake", "-S", source / "examples" / "cpp", "-B", work / "example", *cmake_args)
    sh("cmake", "--build", work / "example")
    out = dict(line.split(" ", 1) for line in sh(work / "example" / "diffusion", cwd=work, env=env).splitlines())
    check(out["billiards"] == version[1], f"library version {out['billiards']} != billiard {version[1]}")

    # The same scene through the installed program: the same geometry, coefficients and ensemble.
    scene = data / "scenes" / "clover-driven.yaml"
    check(pathlib.Path(out["scene"]) == scene, f"the example read {out['scene']}")
    coeffs = json.loads(sh(billiard, "coeffs", scene, "--json", env=env))
    for key in ("V", "S", "mean_free_path", "C"):
        check(float(out[key]) == coeffs[key], f"{key}: example {out[key]} != billiard coeffs {coeffs[key]}")
    sh(billiard, "run", scene, "--particles", out["particles"], "--time", out["time"], "--quiet", "--no-csv",
       "--out", work / "run", cwd=work, env=env)
    run = json.loads((work / "run" / "summary.json").read_text())
    check(int(out["collisions"]) == run["collisions"], "collision counts differ")
    for key in ("mean_dE", "var_dE"):
        check(float(out[key].split()[0]) == run[key], f"{key}: example {out[key]} != billiard run {run[key]}")
    print(f"installed into {prefix}: billiard {version[1]}, examples/cpp built and equal to billiard's numbers")


if __name__ == "__main__":
    main()
