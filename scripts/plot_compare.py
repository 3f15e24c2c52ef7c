#!/usr/bin/python3
"""The figure of a `billiard compare` output directory.

    plot_compare.py DIR        writes DIR/comparison.png

Top row: the energy histogram at up to four recorded times (steps), the Fokker-Planck density
eta(E, t) averaged over each bin (dots) and as a curve (from fokker-planck.csv), with the
Kolmogorov-Smirnov distance (p-value) and the L1 distance beside the L1 that sampling noise
alone would give.  Bottom row: <dE> and Var(dE) against t with 1-SE error bars, the
short-time prediction g1 t, g2 t, and the Fokker-Planck moments (exact, or with a potential
those of the numerical solution, whose eta fokker-planck.csv then holds).
"""
import json
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import plot_common  # noqa: E402
from plot_common import UNITS, plt  # noqa: E402


def main(run):
    comparison = json.load(open(os.path.join(run, "comparison.json")))
    times = comparison["times"]
    hist = np.loadtxt(os.path.join(run, "comparison.csv"), delimiter=",", skiprows=1, ndmin=2)
    fp = np.loadtxt(os.path.join(run, "fokker-planck.csv"), delimiter=",", skiprows=1, ndmin=2)
    summary = json.load(open(os.path.join(run, "summary.json")))
    record_times = summary["record_times"]

    picks = sorted({int(round(i)) for i in np.linspace(0, len(times) - 1, min(4, len(times)))})
    fig = plt.figure(figsize=(4.2 * max(len(picks), 2), 7.2))
    grid = fig.add_gridspec(2, max(len(picks), 2))
    for col, k in enumerate(picks):
        ax = fig.add_subplot(grid[0, col])
        f = times[k]
        rows = hist[hist[:, 0] == f["t"]]
        ax.stairs(rows[:, 3], np.append(rows[:, 1], rows[-1, 2]), color="#468", label="simulation")
        centers = 0.5 * (rows[:, 1] + rows[:, 2])
        ax.plot(centers, rows[:, 4], ".", color="k", ms=3, label="Fokker–Planck, bin average")
        column = 1 + record_times.index(f["t"])
        inside = (fp[:, 0] >= rows[0, 1]) & (fp[:, 0] <= rows[-1, 2])
        ax.plot(fp[inside, 0], fp[inside, column], "k-", lw=0.8, label="Fokker–Planck η(E, t)")
        if plot_common.spans_decades(np.append(rows[:, 1], rows[-1, 2])):  # E over decades: its tail
            ax.set_yscale("log")
        ax.set_title(f"t = {f['t']:g}:  KS D = {f['ks_distance']:.3g} (p = {f['ks_p_value']:.2g})\n"
                     f"L1 = {f['l1_distance']:.3g} (sampling noise alone: {f['l1_expected_from_noise']:.3g})",
                     fontsize=9)
        ax.set_xlabel(f"energy E ({UNITS})")
        if col == 0:
            ax.set_ylabel("probability density of E")
            ax.legend(fontsize=7, loc="center right")

    pred = comparison["prediction"]
    # With a potential (closed_form false) the Fokker-Planck law is the numerical solution.
    fp_label = "Fokker–Planck, exact moments" if pred["closed_form"] else "Fokker–Planck, numerical solution"
    column = lambda key, start: np.array([start] + [f[key] for f in times])  # noqa: E731
    axes = (fig.add_subplot(grid[1, 0]), fig.add_subplot(grid[1, 1]))
    plot_common.moments_panels(axes, column("t", 0), column("mean_dE", 0), column("se_mean_dE", 0),
                               column("var_dE", 0), column("se_var_dE", 0), column("g1_t", 0), column("g2_t", 0),
                               column("fp_mean_dE", 0), column("fp_var_dE", 0), fp_label)
    fig.suptitle(f"{plot_common.scene_title(summary)}: simulation against the Fokker–Planck law", fontsize=11)
    fig.tight_layout()
    plot_common.save(fig, os.path.join(run, "comparison.png"), dpi=110)


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    try:
        main(sys.argv[1])
    except (OSError, ValueError, KeyError) as e:  # a missing or malformed run: one line, no traceback
        sys.exit(f"plot_compare.py: error: {e}")
