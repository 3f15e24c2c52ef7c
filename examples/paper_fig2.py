#!/usr/bin/env python3
"""The paper's Fig. 2 from Python: the energy distribution of the driven clover at t = 10, 100,
1000 for omega = 40 pi, histograms of a simulated ensemble against the Fokker-Planck prediction
(analytic, eq. B4, and the numerical Chang-Cooper solution).

    python3 examples/paper_fig2.py [--quick] [--particles N] [--output fig2.png]

with billiardkit installed (docs/python.md), or PYTHONPATH=build/python.

N = 4000 by default (about 8 s on 2 cores); the paper used --particles 100000.
"""
import argparse
import os
import pathlib

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import billiardkit as bk  # noqa: E402

ROOT = pathlib.Path(__file__).resolve().parents[1]


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--particles", type=int, default=4000, help="ensemble size (the paper: 100000)")
    parser.add_argument("--times", default="10,100,1000", help="times of the histograms")
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--threads", type=int, default=0, help="0: all cores")
    parser.add_argument("--output", default="out/paper-fig2-python.png")
    parser.add_argument("--quick", action="store_true", help="300 particles to t = 1, 2, 5 (seconds)")
    args = parser.parse_args()
    if args.quick:
        args.particles, args.times = 300, "1,2,5"
    times = [float(t) for t in args.times.split(",")]

    # The paper's setup is scenes/clover-driven.yaml (m = 1, E0 = 1/2, F = 10 along (1, 1)/sqrt 2);
    # here the same scene is written as a dict, with omega = 40 pi and the record times of the figure.
    scene = bk.load_scene({
        "shape": "shapes/clover.yaml",
        "parameters": {"F": 10, "omega": "40*pi"},
        "initial": {"microcanonical": {"energy": "1/2"}},
        "force": {"periodic": {"amplitude": ["F/sqrt(2)", "F/sqrt(2)"], "omega": "omega"}},
        "run": {"particles": args.particles, "time": max(times), "record": times, "seed": args.seed},
    }, base_dir=ROOT)
    c = bk.coefficients(scene)
    print(f"lambda = {c['mean_free_path']:.5g}, C = {c['C']:.5g}; running {scene.particles} particles to "
          f"t = {scene.time:g} ...")

    run = bk.run(scene, threads=args.threads)  # the GIL is released; the arrays are not copied
    print(f"{run['collisions'].sum()} collisions in {run['seconds']:.2f} s, {run['escaped'].sum()} escapes")

    s = c["C"] * np.array(times)
    E_num, eta_num, _ = bk.fokker_planck_numerical(s, scene.energy)
    fig, axes = plt.subplots(1, len(times), figsize=(4.5 * len(times), 3.6))
    for ax, t, sk, eta in zip(np.atleast_1d(axes), times, s, eta_num):
        k = int(np.searchsorted(run["record_times"], t))
        E = run["energies"][:, k]
        E = E[np.isfinite(E)]
        top = 1.1 * np.quantile(E, 0.995)  # the far tail would squeeze the bulk
        ax.hist(E, bins=60, range=(0, top), weights=np.full(len(E), 60 / top / len(E)), color="#9ab",
                label=f"simulation (N = {len(E)})")  # a density over all N particles, tail included
        grid = np.linspace(0, top, 600)[1:]
        ax.plot(grid, bk.fokker_planck_eta(grid, sk, scene.energy), "k-", lw=1.2, label="Fokker-Planck (B4)")
        ax.plot(E_num, eta, "r--", lw=1, label="Fokker-Planck (numerical)")
        ax.set_xlim(0, top)
        ax.set_title(f"t = {t:g}")
        ax.set_xlabel("E")
    np.atleast_1d(axes)[0].set_ylabel(r"$\eta(E, t)$")
    np.atleast_1d(axes)[0].legend(fontsize=8)
    fig.suptitle(r"driven clover, $\omega = 40\pi$: energy distribution (paper's Fig. 2)")
    fig.tight_layout()

    out = pathlib.Path(args.output)
    out.parent.mkdir(parents=True, exist_ok=True)
    tmp = out.with_suffix(".tmp.png")
    fig.savefig(tmp, dpi=120)
    os.replace(tmp, out)  # the PNG appears only when complete
    print(f"wrote {out}")


if __name__ == "__main__":
    main()
