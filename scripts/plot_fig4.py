#!/usr/bin/python3
"""The paper's Fig. 4 from runs at several frequencies.

    plot_fig4.py OUT_DIR RUN_DIR...     writes OUT_DIR/fig4.png and OUT_DIR/fig4.csv

Each RUN_DIR is a `billiard run` output of the same scene at one omega.
"""
import json
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    out, runs = sys.argv[1], sys.argv[2:]
    rows = []
    for run in runs:
        with open(os.path.join(run, "summary.json")) as f:
            s = json.load(f)
        p, T = s["prediction"], s["time"]
        rows.append((s["omega"], s["mean_dE"], s["se_mean_dE"], p["g1"] * T, s["fp_mean_dE"],
                     s["var_dE"], s["se_var_dE"], p["g2"] * T, s["fp_var_dE"], s["particles"]))
    rows.sort()
    with open(os.path.join(out, "fig4.csv"), "w") as f:
        f.write("omega,mean_dE,se_mean_dE,g1_dt,fp_mean_dE,var_dE,se_var_dE,g2_dt,fp_var_dE,particles\n")
        for r in rows:
            f.write(",".join(f"{x:.10g}" for x in r) + "\n")
    w = [r[0] / math.pi for r in rows]
    fig, axes = plt.subplots(1, 2, figsize=(10, 4))
    for ax, i, label in ((axes[0], 1, r"$\langle\Delta E\rangle$"), (axes[1], 5, r"Var$(\Delta E)$")):
        ax.errorbar(w, [r[i] for r in rows], yerr=[r[i + 1] for r in rows], fmt="o", ms=4, capsize=2,
                    label="simulation")
        ax.plot(w, [r[i + 2] for r in rows], "k-", lw=1, label=r"$g\,\Delta t$ (theory)")
        ax.set_xscale("log", base=2)
        ax.set_yscale("log")
        ax.set_xlabel(r"$\omega/\pi$")
        ax.set_ylabel(label)
        ax.legend(fontsize=8)
    fig.suptitle(f"clover, E0 = 1/2, F = 10, dt = 20, N = {rows[0][-1]} per frequency")
    fig.tight_layout()
    tmp = os.path.join(out, "fig4.tmp.png")
    fig.savefig(tmp, dpi=120)
    os.replace(tmp, os.path.join(out, "fig4.png"))


if __name__ == "__main__":
    try:
        main()
    except (OSError, ValueError, KeyError) as e:  # a missing or malformed run: one line, no traceback
        sys.exit(f"plot_fig4.py: error: {e}")
