"""What the figures of a run share: their titles, the moments panels and the way they are saved.

Every figure of a run is titled by the same words (scene_title), draws the moments the same way
(moments_panels) and is written whole or not at all (save).  The toolkit has no units of its
own: the bundled scenes use m = 1 and tables of size ~1, so their quantities are dimensionless.
"""
import math
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

UNITS = "dimensionless"
FORMATS = ("png", "pdf", "svg")


def scene_title(summary):
    """'clover-driven (clover): F = 10, ω = 40π, N = 20000' — the scene file's name, its shape,
    the drive's amplitude |F| and frequency, and the number of particles."""
    scene = os.path.splitext(os.path.basename(summary["scene"]))[0]
    F = math.hypot(*summary.get("F", [0.0]))
    force = summary.get("force", "none")
    if force == "none" or F == 0 and force != "field":
        drive = "free (F = 0)"
    elif force == "constant":
        drive = f"static force F = {F:.4g}"
    elif force == "field":
        drive = f"field F(x), ω = {summary['omega'] / math.pi:.4g}π"
    else:
        drive = f"F = {F:.4g}, ω = {summary['omega'] / math.pi:.4g}π"
    return f"{scene} ({summary['shape']}): {drive}, N = {summary['particles']}"


def moments_panels(axes, t, mean, se_mean, var, se_var, g1_t=None, g2_t=None, fp_mean=None, fp_var=None,
                   fp_label="Fokker–Planck, exact moments"):
    """⟨ΔE⟩ and Var ΔE against t: the simulation with 1-SE error bars, the Fokker–Planck moments
    (solid) and the short-time lines g1 t, g2 t (dashed, drawn over the solid line so that both
    stay visible where they coincide).  Curves that are None are left out."""
    rows = ((axes[0], mean, se_mean, g1_t, fp_mean, "⟨ΔE⟩", "g1 t"),
            (axes[1], var, se_var, g2_t, fp_var, "Var ΔE", "g2 t"))
    for ax, y, se, short, exact, name, short_name in rows:
        if exact is not None:
            ax.plot(t, exact, "-", color="black", lw=2.2, alpha=0.35, label=fp_label, zorder=1)
        if short is not None:
            ax.plot(t, short, "--", color="tab:red", lw=1.1, label=f"short time: {short_name}", zorder=2)
        ax.errorbar(t, y, yerr=se, fmt="o", ms=3, capsize=2, color="tab:blue",
                    label="simulation (error bars: 1 SE)", zorder=3)
        if spans_decades(t, 1.5):  # record times such as 10, 100, 1000
            ax.set_xscale("log")
            if np.all(np.asarray(y)[np.asarray(t) > 0] > 0):
                ax.set_yscale("log")
        ax.set_xlabel(f"time t ({UNITS})")
        ax.set_ylabel(f"{name}\n(ΔE = E(t) − E(0), {UNITS})")
        ax.legend(fontsize=7)


def spans_decades(values, decades=2.0):
    """True when the positive values span more than `decades` powers of ten."""
    v = np.asarray(values, dtype=float)
    v = v[np.isfinite(v) & (v > 0)]
    return len(v) > 1 and math.log10(v.max() / v.min()) > decades


def format_of(path):
    """The output format named by the file's extension: png, pdf or svg."""
    ext = os.path.splitext(path)[1].lower().lstrip(".")
    if ext not in FORMATS:
        raise SystemExit(f"{path}: the extension must be one of .png, .pdf, .svg")
    return ext


def save(fig, path, dpi=120):
    """Writes the figure to a temporary file beside `path` and renames it into place, so that
    `path` is either the whole figure or untouched."""
    ext = format_of(path)
    tmp = f"{path}.tmp-{os.getpid()}.{ext}"
    fig.savefig(tmp, dpi=dpi, format=ext)
    os.replace(tmp, path)
    plt.close(fig)
