#!/usr/bin/python3
"""Draws the boundary map, a line section or a stroboscopic section written by `billiard bmap`.

    plot_bmap.py INPUT.json OUTPUT.png|OUTPUT.pdf|OUTPUT.svg

INPUT.json is the metadata `billiard bmap` writes beside its .npy: "kind" ("bmap", "section", "section3",
"strobe" or "strobe3": its positions drawn projected on the x-y plane), "npy" (the rows, relative to INPUT.json), "columns", "perimeter", "piece_starts"
(s at each piece's start), "loop_firsts", "shape", "force", "particles", "collisions".
Points are coloured by particle; at most MAX_POINTS of them are drawn (every k-th row).
"""
import json
import os
import sys

try:
    import matplotlib
except ImportError:
    sys.exit("plot_bmap.py: matplotlib is missing (Debian: apt install python3-matplotlib)")
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

MAX_POINTS = 2_000_000


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    with open(sys.argv[1]) as f:
        meta = json.load(f)
    rows = np.load(os.path.join(os.path.dirname(sys.argv[1]), meta["npy"]))
    step = max(1, len(rows) // MAX_POINTS)
    rows = rows[::step]
    col = {name: i for i, name in enumerate(meta["columns"])}
    kind = meta["kind"]
    fig, ax = plt.subplots(figsize=(7.5, 4.6))
    particle = rows[:, col["particle"]] if len(rows) else np.zeros(0)
    size = max(0.05, min(4.0, 4e4 / max(1, len(rows))))
    if kind == "bmap":
        x, y = rows[:, col["s"]], rows[:, col["p"]]
        S = meta["perimeter"]
        for s in meta["piece_starts"][1:-1]:
            ax.axvline(s, color="#bbbbbb", lw=0.6, zorder=0)
        for first in meta["loop_firsts"][1:]:
            ax.axvline(meta["piece_starts"][first], color="#555555", lw=1.2, zorder=0)
        ax.set_xlim(0, S)
        ax.set_ylim(-1, 1)
        ax.set_xlabel(f"s: arc length along the boundary (outer loop, then the holes; S = {S:.6g})")
        ax.set_ylabel("p = sin φ (φ: outgoing velocity from the inward normal)")
        what = "boundary map"
    elif kind == "section3":
        x, y = rows[:, col["u1"]], rows[:, col["u2"]]
        ax.set_aspect("equal")
        ax.set_xlabel(f"u1: position in the plane {meta['section']} (along e1)")
        ax.set_ylabel("u2 (along e2 = n x e1)")
        what = f"Poincaré section {meta['section']}"
    elif kind == "section":
        x, y = rows[:, col["u"]], rows[:, col["p"]]
        ax.set_ylim(-1, 1)
        ax.set_xlabel(f"u: position along the line {meta['section']}")
        ax.set_ylabel("p = velocity along the line / speed")
        what = f"Poincaré section {meta['section']}"
    else:
        x, y = rows[:, col["x"]], rows[:, col["y"]]
        ax.set_aspect("equal")
        ax.set_xlabel("x" + (" (positions projected on the x-y plane)" if kind == "strobe3" else ""))
        ax.set_ylabel("y")
        what = f"stroboscopic section at drive phase {meta['strobe']:.6g}"
    ax.scatter(x, y, c=particle, s=size, cmap="tab10" if meta["particles"] <= 10 else "viridis",
               linewidths=0, rasterized=True)
    note = f", every {step}th point" if step > 1 else ""
    ax.set_title(f"{meta['shape']} ({meta['force']}): {what}\n{meta['particles']} particles x "
                 f"{meta['collisions']} collisions, colour = particle{note}", fontsize=10)
    output = sys.argv[2]
    try:
        fig.savefig(output, dpi=150, format=output.rsplit(".", 1)[-1].lower(), bbox_inches="tight")
    except OSError as e:
        sys.exit(f"plot_bmap.py: cannot write {output}: {e.strerror}")


if __name__ == "__main__":
    main()
