#!/usr/bin/python3
"""Draws the survival probability P(t) written by `billiard escape`, on a log scale, with the
exponential law exp(-t / tau) of Kac's mean tau = pi V / (w v) (2-D; 4 V / (A v) in 3-D).

    plot_escape.py DIR OUTPUT.png
"""
import json
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    folder = sys.argv[1]
    with open(os.path.join(folder, "escape.json")) as f:
        meta = json.load(f)
    t, P = np.loadtxt(os.path.join(folder, "survival.csv"), delimiter=",", skiprows=1, unpack=True)
    fig, ax = plt.subplots(figsize=(6.5, 4.2))
    keep = P > 0
    ax.semilogy(t[keep], P[keep], "-", color="#1f3b57", label=f"simulation ({meta['ensemble']}, N = {meta['particles']})")
    tau = meta["kac_mean_escape_time"]
    kac = "4V/(Av)" if meta.get("dimension") == 3 else "πV/(wv)"
    ax.semilogy(t, np.exp(-t / tau), "--", color="#c0392b", label=f"exp(-t / τ), τ = {kac} = {tau:.4g}")
    ax.set_xlabel("t (time since the start)")
    ax.set_ylabel("P(t): fraction still inside")
    ax.set_title(f"{meta['shape']}: escape through exits of length w = {meta['exit_length']:.4g}\n"
                 f"mean escape time {meta['mean_escape_time']:.4g} ± {meta['mean_escape_time_se']:.2g}", fontsize=10)
    ax.legend(fontsize=8)
    fig.savefig(sys.argv[2], dpi=150, bbox_inches="tight")


if __name__ == "__main__":
    main()
