#!/usr/bin/python3
"""The parallel-wall echo's prediction for a Sinai table (square or cube of side 1 minus a
centred disk or ball) under the drive F (1, ..., 1)/sqrt(d) cos(omega t), m = 1, speed 1.

Along free paths (the module's `trajectory`), every three hits p, m, q on the two walls normal to
one axis with no scatterer hit between (so equal flight times before and after m) add
-4 w^2 F_a^2 J2(2 |F_a| L / w^2) / omega^2 to Var dE (w the normal speed at m, L = 1); the
theory's g2 dt is the sum of 2 w^2 (F.n)^2 / omega^2 over all hits.  Prints their ratio, the
relative correction to Var dE, which does not depend on omega (docs/3d.md, "The Sinai tables' excess of Var ΔE").  With
--window DT only triples within one interval [j DT, (j + 1) DT) count, as in an ensemble run over DT.

  PYTHONPATH=build/python bench/sinai_echo.py shapes/sinai.yaml --F 10 --window 10
"""
import argparse

import numpy as np
from scipy.special import jv

import billiards


def echo_ratio(shape, F, collisions, window, seeds=10):
    d = shape.dimension
    Fv = F / np.sqrt(d) * np.ones(d)
    white = echo = 0.0
    for seed in range(1, seeds + 1):
        path = billiards.trajectory(shape, collisions=collisions // seeds, seed=seed)
        x, v, t = path["positions"][1:], path["velocities"][1:], path["times"][1:]
        axis = np.full(len(x), -1)  # the axis of a flat wall's normal; -1 on the scatterer
        for k in range(d):
            axis[np.abs(np.abs(x[:, k]) - 0.5) < 1e-9] = k
        n = -x / np.linalg.norm(x, axis=1)[:, None]  # outward from the region on the scatterer
        for k in range(d):
            n[axis == k] = 0
            n[axis == k, k] = np.sign(x[axis == k, k])
        a = np.abs(np.sum(v * n, axis=1))
        white += np.sum(2 * a**2 * (n @ Fv) ** 2)
        last, before = [-1] * d, [-1] * d  # the axis's last two wall hits since the scatterer
        for k in range(len(x)):
            if axis[k] < 0:
                last, before = [-1] * d, [-1] * d
                continue
            ax = axis[k]
            if before[ax] >= 0 and np.floor(t[before[ax]] / window) == np.floor(t[k] / window):
                s2 = a[last[ax]] ** 2
                echo += -4 * s2 * Fv[ax] ** 2 * jv(2, 2 * abs(Fv[ax]) / s2)
            before[ax], last[ax] = last[ax], k
    return echo / white


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("shape")
    p.add_argument("--F", type=float, default=10)
    p.add_argument("--R", type=float, default=0.25)
    p.add_argument("--collisions", type=int, default=400000)
    p.add_argument("--window", type=float, default=np.inf)
    args = p.parse_args()
    shape = billiards.load_shape(args.shape, set={"R": args.R})
    ratio = echo_ratio(shape, args.F, args.collisions, args.window)
    print(f"{args.shape} F={args.F} R={args.R} window={args.window}: echo / g2 dt = {ratio:+.4f}")


if __name__ == "__main__":
    main()
