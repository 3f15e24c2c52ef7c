#!/usr/bin/python3
"""Figures of a `billiard run` output directory.

    plot_run.py DIR            writes DIR/energy-histograms.png and DIR/energy-moments.png

energy-histograms.png: the energy distribution at (up to) three record times, with the
Fokker-Planck prediction eta(E, t) drawn over it when DIR/fokker-planck.csv exists (written by
`billiard run` for driven scenes: a column E, then one column per record time).
energy-moments.png: <dE> and Var(dE) against t with their standard errors, and g1 t, g2 t when
summary.json has a "prediction".
"""
import json
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def save(fig, path):
    tmp = path + ".tmp.png"
    fig.savefig(tmp, dpi=120)
    os.replace(tmp, path)
    plt.close(fig)


def histograms(run, summary, energies):
    times = summary["record_times"]
    picks = sorted({len(times) - 1, max(1, len(times) // 10), max(1, len(times) // 2)})
    fig, axes = plt.subplots(1, len(picks), figsize=(4.5 * len(picks), 3.6))
    fp_path = os.path.join(run, "fokker-planck.csv")
    fp = np.loadtxt(fp_path, delimiter=",", skiprows=1, ndmin=2) if os.path.exists(fp_path) else None
    for ax, k in zip(np.atleast_1d(axes), picks):
        E = energies[:, k]
        E = E[np.isfinite(E)]
        ax.hist(E, bins=80, density=True, color="#9ab", label="simulation")
        if fp is not None and times[k] > 0:
            ax.plot(fp[:, 0], fp[:, 1 + k], "k-", lw=1.2, label="Fokker-Planck")
            ax.set_xlim(E.min(), E.max())
        ax.set_title(f"t = {times[k]:g}")
        ax.set_xlabel("E")
    np.atleast_1d(axes)[0].set_ylabel("density")
    np.atleast_1d(axes)[0].legend(fontsize=8)
    fig.suptitle(f"{summary['shape']}: energy distribution, N = {summary['particles']}")
    fig.tight_layout()
    save(fig, os.path.join(run, "energy-histograms.png"))


def moments(run, summary):
    per = summary["per_time"]
    t = np.array([p["t"] for p in per])
    pred = summary.get("prediction", {})
    fig, axes = plt.subplots(1, 2, figsize=(9, 3.6))
    for ax, key, se, g in ((axes[0], "mean_dE", "se_mean_dE", "g1"), (axes[1], "var_dE", "se_var_dE", "g2")):
        y = np.array([p[key] for p in per])
        e = np.array([p[se] for p in per])
        ax.errorbar(t, y, yerr=e, fmt="o", ms=3, label="simulation")
        if g in pred:
            ax.plot(t, pred[g] * t, "k-", label=f"{g} t")
        ax.set_xlabel("t")
        ax.set_ylabel(key.replace("_dE", "(dE)"))
        ax.legend(fontsize=8)
    fig.tight_layout()
    save(fig, os.path.join(run, "energy-moments.png"))


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    run = sys.argv[1]
    with open(os.path.join(run, "summary.json")) as f:
        summary = json.load(f)
    energies = np.load(os.path.join(run, "energies.npy"))
    histograms(run, summary, energies)
    moments(run, summary)


if __name__ == "__main__":
    try:
        main()
    except (OSError, ValueError, KeyError) as e:  # a missing or malformed run: one line, no traceback
        sys.exit(f"plot_run.py: error: {e}")
