#!/usr/bin/python3
"""Draws a shape (and a trajectory) from the JSON written by `billiard plot`.

    plot_shape.py INPUT.json OUTPUT.png
"""
import json
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.path import Path  # noqa: E402
from matplotlib.patches import PathPatch  # noqa: E402


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    with open(sys.argv[1]) as f:
        data = json.load(f)
    fig, ax = plt.subplots(figsize=(6, 6))
    # One compound path: the outer loop and the holes (even-odd fill leaves the holes empty).
    vertices, codes = [], []
    for loop in data["loops"]:
        vertices += loop + [loop[0]]
        codes += [Path.MOVETO] + [Path.LINETO] * (len(loop) - 1) + [Path.CLOSEPOLY]
    ax.add_patch(PathPatch(Path(vertices, codes), facecolor="#e8eef4", edgecolor="#1f3b57", lw=1.5))
    if data["trajectory"]:
        xs, ys = zip(*data["trajectory"])
        ax.plot(xs, ys, "-", color="#c0392b", lw=0.6, alpha=0.8)
        ax.plot(xs[:1], ys[:1], "o", color="#c0392b", ms=4)
    ax.set_aspect("equal")
    ax.autoscale_view()
    ax.margins(0.05)
    ax.set_title(data["title"], fontsize=10)
    fig.tight_layout()
    tmp = sys.argv[2] + ".tmp.png"
    fig.savefig(tmp, dpi=130)
    os.replace(tmp, sys.argv[2])


if __name__ == "__main__":
    main()
