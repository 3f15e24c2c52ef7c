#!/usr/bin/env python3
"""Draws speed-error.csv (written by `billiard bench speed-error`): CPU seconds per simulated
time per particle against the error of Var(dE), log-log, one curve per method and drive
frequency.  Usage: plot_speed_error.py speed-error.csv speed-error.png"""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main(csv_path, png_path):
    with open(csv_path, newline="") as f:
        rows = list(csv.DictReader(f))
    fig, ax = plt.subplots(figsize=(7, 5))
    omegas = sorted({float(r["omega_over_pi"]) for r in rows})
    colors = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    # An error of exactly 0 cannot be drawn on a log axis: it is shown at the axis floor.
    floor = 1e-18
    for k, w in enumerate(omegas):
        color = colors[k % len(colors)]
        for method, marker, style in (("odeint", "o", "-"), ("exact", "*", "none")):
            sel = [r for r in rows if r["method"] == method and float(r["omega_over_pi"]) == w]
            if not sel:
                continue
            sel.sort(key=lambda r: float(r["tolerance"]), reverse=True)
            x = [max(float(r["var_dE_error"]), floor) for r in sel]
            y = [float(r["cpu_seconds_per_time"]) for r in sel]
            label = f"{'Odeint dopri5' if method == 'odeint' else 'exact flight (vs MPFR)'}, ω = {w:g}π"
            ax.plot(x, y, marker=marker, linestyle=style, color=color, label=label,
                    markersize=12 if method == "exact" else 5)
            for r, xi, yi in zip(sel, x, y):
                if method == "odeint":
                    note = f"{float(r['tolerance']):.0e}"
                    if int(r["escapes"]):
                        note += f" ({r['escapes']} esc.)"
                    ax.annotate(note, (xi, yi), fontsize=6, xytext=(3, 3), textcoords="offset points")
        se = float(next(r["var_dE_se"] for r in rows if float(r["omega_over_pi"]) == w))
        ax.axvline(se, color=color, linestyle=":", linewidth=0.8)
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("|error of Var(ΔE) at the end time|  (dotted: sampling SE of Var(ΔE))")
    ax.set_ylabel("CPU seconds per simulated time unit per particle")
    ax.set_title("Speed against error (same initial conditions for every method)", fontsize=10)
    ax.grid(True, which="both", linewidth=0.3)
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(png_path, dpi=120)


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    main(sys.argv[1], sys.argv[2])
