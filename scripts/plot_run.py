#!/usr/bin/python3
"""Figures of a `billiard run` output directory.

    plot_run.py DIR            writes DIR/energy-histograms.png and DIR/energy-moments.png

When the energies change (a driven scene):
energy-histograms.png: the distribution of E at (up to) three record times, with the
Fokker-Planck density eta(E, t) of DIR/fokker-planck.csv drawn over it when it exists; log axes
when E spans decades.
energy-moments.png: <dE> and Var(dE) against t with 1-SE error bars, the exact Fokker-Planck
moments and the short-time lines g1 t, g2 t (summary.json's per_time).
When every energy stays at its start (a free scene, energy conserved):
energy-histograms.png: the distribution of the relative energy error |E(T) - E(0)|/E(0).
energy-moments.png: the largest and the root-mean-square relative energy error against t.
"""
import json
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import plot_common  # noqa: E402
from plot_common import UNITS, plt  # noqa: E402

# Relative energy changes below this are rounding: the run conserves energy.
CONSERVED = 1e-12


def picks_of(times):
    """Three record times after the start: early, middle and last."""
    return sorted({len(times) - 1, max(1, len(times) // 10), max(1, len(times) // 2)})


def histograms(run, summary, energies):
    times = summary["record_times"]
    picks = picks_of(times)
    fig, axes = plt.subplots(1, len(picks), figsize=(4.5 * len(picks), 3.8), squeeze=False)
    fp_path = os.path.join(run, "fokker-planck.csv")
    fp = np.loadtxt(fp_path, delimiter=",", skiprows=1, ndmin=2) if os.path.exists(fp_path) else None
    for ax, k in zip(axes[0], picks):
        E = energies[:, k]
        E = E[np.isfinite(E)]
        log = plot_common.spans_decades(E) and E.min() > 0
        bins = np.geomspace(E.min(), E.max(), 80) if log else 80
        ax.hist(E, bins=bins, density=True, color="#9ab", label="simulation")
        if fp is not None and times[k] > 0:
            inside = (fp[:, 0] >= E.min()) & (fp[:, 0] <= E.max())
            ax.plot(fp[inside, 0], fp[inside, 1 + k], "k-", lw=1.2, label="Fokker–Planck η(E, t)")
        if log:
            ax.set_xscale("log")
            ax.set_yscale("log")
        ax.set_title(f"t = {times[k]:g}", fontsize=10)
        ax.set_xlabel(f"energy E ({UNITS})")
    axes[0][0].set_ylabel("probability density of E")
    axes[0][0].legend(fontsize=8)
    fig.suptitle(f"{plot_common.scene_title(summary)}: energy distribution", fontsize=11)
    fig.tight_layout()
    plot_common.save(fig, os.path.join(run, "energy-histograms.png"))


def moments(run, summary):
    per = summary["per_time"]
    column = lambda key: np.array([p[key] for p in per]) if key in per[0] else None  # noqa: E731
    fig, axes = plt.subplots(1, 2, figsize=(10, 4))
    plot_common.moments_panels(axes, column("t"), column("mean_dE"), column("se_mean_dE"), column("var_dE"),
                               column("se_var_dE"), column("g1_t"), column("g2_t"), column("fp_mean_dE"),
                               column("fp_var_dE"))
    fig.suptitle(f"{plot_common.scene_title(summary)}: moments of the energy change", fontsize=11)
    fig.tight_layout()
    plot_common.save(fig, os.path.join(run, "energy-moments.png"))


def conservation(run, summary, energies):
    """The free billiard conserves E: its figures show how well, instead of a δ at E(0)."""
    t = np.array(summary["record_times"])
    error = np.abs(energies - energies[:, :1]) / energies[:, :1]
    exact = int(np.sum(error[:, -1] == 0))
    title = plot_common.scene_title(summary)

    fig, ax = plt.subplots(figsize=(6, 4))
    nonzero = error[:, -1][error[:, -1] > 0]
    if len(nonzero):
        ax.hist(nonzero, bins=np.geomspace(nonzero.min(), nonzero.max() * 1.01, 40), color="#9ab")
        ax.set_xscale("log")
    ax.set_xlabel(f"relative energy error |E(T) − E(0)| / E(0) at T = {t[-1]:g}")
    ax.set_ylabel("particles")
    ax.set_title(f"{exact} of {len(error)} particles with E(T) = E(0) exactly (not drawn)", fontsize=9)
    fig.suptitle(f"{title}: energy conservation", fontsize=10)
    fig.tight_layout()
    plot_common.save(fig, os.path.join(run, "energy-histograms.png"))

    fig, ax = plt.subplots(figsize=(6, 4))
    floor = np.finfo(float).eps / 4  # an error of exactly 0, drawn at the axis' floor
    ax.semilogy(t, np.maximum(error.max(axis=0), floor), "o-", ms=3, label="largest over the particles")
    ax.semilogy(t, np.maximum(np.sqrt((error ** 2).mean(axis=0)), floor), "s-", ms=3, label="root mean square")
    ax.axhline(np.finfo(float).eps, color="gray", ls=":", lw=1, label="double precision ε")
    ax.set_xlabel(f"time t ({UNITS})")
    ax.set_ylabel("relative energy error |E(t) − E(0)| / E(0)")
    ax.legend(fontsize=8)
    ax.set_title("an error of exactly 0 is drawn at ε/4", fontsize=9)
    fig.suptitle(f"{title}: energy conservation", fontsize=10)
    fig.tight_layout()
    plot_common.save(fig, os.path.join(run, "energy-moments.png"))


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    run = sys.argv[1]
    with open(os.path.join(run, "summary.json")) as f:
        summary = json.load(f)
    energies = np.load(os.path.join(run, "energies.npy"))
    finite = energies[np.isfinite(energies).all(axis=1)]
    if np.all(np.abs(finite - finite[:, :1]) <= CONSERVED * np.abs(finite[:, :1])):
        conservation(run, summary, finite)
        return
    histograms(run, summary, energies)
    moments(run, summary)


if __name__ == "__main__":
    try:
        main()
    except (OSError, ValueError, KeyError) as e:  # a missing or malformed run: one line, no traceback
        sys.exit(f"plot_run.py: error: {e}")
