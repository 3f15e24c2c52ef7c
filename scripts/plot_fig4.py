#!/usr/bin/python3
"""The paper's Fig. 4 from runs at several frequencies.

    plot_fig4.py OUT_DIR RUN_DIR...     writes OUT_DIR/fig4.png and OUT_DIR/fig4.csv

Each RUN_DIR is a `billiard run` output of the same scene at one omega.
"""
import json
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import plot_common  # noqa: E402
from plot_common import UNITS, plt  # noqa: E402


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    out, runs = sys.argv[1], sys.argv[2:]
    rows, first = [], None
    for run in runs:
        with open(os.path.join(run, "summary.json")) as f:
            s = json.load(f)
        first = first or s
        p, T = s["prediction"], s["time"]
        rows.append((s["omega"], s["mean_dE"], s["se_mean_dE"], p["g1"] * T, s["fp_mean_dE"],
                     s["var_dE"], s["se_var_dE"], p["g2"] * T, s["fp_var_dE"], s["particles"]))
    rows.sort()
    with open(os.path.join(out, "fig4.csv"), "w") as f:
        f.write("omega,mean_dE,se_mean_dE,g1_dt,fp_mean_dE,var_dE,se_var_dE,g2_dt,fp_var_dE,particles\n")
        for r in rows:
            f.write(",".join(f"{x:.10g}" for x in r) + "\n")
    w = [r[0] / math.pi for r in rows]
    fig, axes = plt.subplots(1, 2, figsize=(10.5, 4.2))
    for ax, i, name in ((axes[0], 1, "⟨ΔE⟩"), (axes[1], 5, "Var ΔE")):
        ax.errorbar(w, [r[i] for r in rows], yerr=[r[i + 1] for r in rows], fmt="o", ms=4, capsize=2,
                    label="simulation (error bars: 1 SE)", zorder=3)
        ax.plot(w, [r[i + 3] for r in rows], "-", color="black", lw=2.2, alpha=0.35,
                label="Fokker–Planck, exact moments", zorder=1)
        ax.plot(w, [r[i + 2] for r in rows], "--", color="tab:red", lw=1.1,
                label=f"short time: {'g1' if i == 1 else 'g2'} Δt", zorder=2)
        ax.set_xscale("log", base=2)
        ax.set_yscale("log")
        ax.set_xlabel("drive frequency ω/π")
        ax.set_ylabel(f"{name} at Δt = {first['time']:g}\n(ΔE = E(Δt) − E(0), {UNITS})")
        ax.legend(fontsize=8)
    title = plot_common.scene_title(first).split(":")[0]
    F = math.hypot(*first["F"])
    fig.suptitle(f"{title}: F = {F:.4g}, E0 = {first['E0']:g}, Δt = {first['time']:g}, "
                 f"N = {rows[0][-1]} per frequency", fontsize=11)
    fig.tight_layout()
    plot_common.save(fig, os.path.join(out, "fig4.png"))


if __name__ == "__main__":
    try:
        main()
    except (OSError, ValueError, KeyError) as e:  # a missing or malformed run: one line, no traceback
        sys.exit(f"plot_fig4.py: error: {e}")
