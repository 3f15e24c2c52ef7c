#!/usr/bin/env python3
"""The paper's Fig. 4 from Python: the driven clover at several drive frequencies omega, the
measured <dE> and Var(dE) at the end time over the theory's g1 t and g2 t.  The theory holds for
large omega (the ratios tend to 1); at small omega the adiabatic conditions fail.

    python3 examples/paper_fig4.py [--quick] [--output fig4.png]
"""
import argparse
import math
import pathlib

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

import billiardkit as bk  # noqa: E402

ROOT = pathlib.Path(__file__).resolve().parents[1]


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--quick", action="store_true", help="three frequencies, small ensembles (seconds)")
    parser.add_argument("--output", default="fig4.png")
    args = parser.parse_args()

    multiples = [10, 40, 160] if args.quick else [5, 10, 20, 40, 80, 160, 320, 640]
    rows = []
    for k in multiples:
        scene = bk.Scene(ROOT / "scenes" / "clover-driven.yaml", omega=k * math.pi,
                         particles=300 if args.quick else 5000, time=5 if args.quick else 20)
        s = bk.run(scene).summary
        rows.append((k, s.mean_dE / s.predicted_mean_dE, s.se_mean_dE / s.predicted_mean_dE,
                     s.var_dE / s.predicted_var_dE, s.se_var_dE / s.predicted_var_dE))
        print(f"omega = {k:4d} pi: <dE>/(g1 t) = {rows[-1][1]:.3f} ± {rows[-1][2]:.3f}, "
              f"Var(dE)/(g2 t) = {rows[-1][3]:.3f} ± {rows[-1][4]:.3f}")

    ax = plt.figure(figsize=(6, 4)).add_subplot()
    w = [r[0] for r in rows]
    ax.errorbar(w, [r[1] for r in rows], yerr=[r[2] for r in rows], fmt="o-", label="<dE> / g1 t")
    ax.errorbar(w, [r[3] for r in rows], yerr=[r[4] for r in rows], fmt="s-", label="Var(dE) / g2 t")
    ax.axhline(1, color="k", lw=0.8)
    ax.set_xscale("log")
    ax.set_xlabel("omega / pi")
    ax.set_ylabel("measured / predicted")
    ax.legend()
    ax.figure.savefig(args.output, dpi=100, bbox_inches="tight")
    print(f"wrote {args.output}")


if __name__ == "__main__":
    main()
