#!/usr/bin/env python3
"""Your own table from Python: a rectangle with a circular hole (a Sinai-like billiard) written as
a dict, its exact geometry, a free trajectory in it, and the same table driven by F cos(omega t)
with the theory's prediction next to a small ensemble.

    python3 examples/own_table.py [--quick] [--output own-table.png]
"""
import argparse
import math

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

import billiardkit as bk  # noqa: E402


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--quick", action="store_true", help="a small ensemble (seconds)")
    parser.add_argument("--output", default="own-table.png")
    args = parser.parse_args()

    table = bk.load_shape({"parameters": {"L": 2, "r": 0.3},
                           "boundary": {"polygon": [[0, 0], ["L", 0], ["L", 1], [0, 1]]},
                           "holes": [{"circle": {"center": ["L/2", 0.5], "radius": "r"}}]})
    info = table.info()
    print(f"V = {info['V']:.15g} (closed form {2 - math.pi * 0.09:.15g}), S = {info['S']:.15g}, "
          f"mean free path = {info['mean_free_path']:.6g}")

    drive = {"periodic": {"amplitude": [0.5, 0], "omega": 60}}
    scene = bk.Scene(table, force=drive, energy=0.5, particles=400 if args.quick else 4000, time=10, record=1)
    res = bk.run(scene)
    s = res.summary
    print(f"Var(dE) at t = {s.t:g}: {s.var_dE:.4g} ± {s.se_var_dE:.2g}, theory g2 t = {s.predicted_var_dE:.4g}")

    fig, (left, right) = plt.subplots(1, 2, figsize=(10, 4))
    bk.plot_trajectory(bk.trajectory(table, collisions=60), table, ax=left)
    bk.plot_run(res, ax=right)
    fig.savefig(args.output, dpi=100, bbox_inches="tight")
    print(f"wrote {args.output}")


if __name__ == "__main__":
    main()
