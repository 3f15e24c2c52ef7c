#!/usr/bin/env python3
"""A charge in the stadium in a magnetic field perpendicular to the plane
(scenes/stadium-magnetic.yaml with a stronger field): between bounces it runs on circles of the
cyclotron radius r_c = m v/(qB), drawn here as arcs, each checked to end at the next bounce.

    python3 examples/magnetic_trajectory.py [--quick] [--B 0.8] [--output magnetic.png]
"""
import argparse
import math
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.patches import Arc  # noqa: E402

import billiardkit as bk  # noqa: E402

SCENE = Path(__file__).resolve().parent.parent / "scenes" / "stadium-magnetic.yaml"


def arc_of(x, v, omega_c, duration):
    """The cyclotron arc from x with velocity v for `duration` (Omega > 0 turns clockwise): its
    centre, radius, start and end angles (radians, counter-clockwise from start to end), and the
    end point."""
    k = abs(omega_c)
    towards = (v[1], -v[0]) if omega_c > 0 else (-v[1], v[0])  # v turned towards the centre
    centre = (x[0] + towards[0] / k, x[1] + towards[1] / k)
    radius = math.hypot(*v) / k
    a0 = math.atan2(x[1] - centre[1], x[0] - centre[0])
    a1 = a0 - k * duration if omega_c > 0 else a0 + k * duration
    end = (centre[0] + radius * math.cos(a1), centre[1] + radius * math.sin(a1))
    return centre, radius, (a1, a0) if omega_c > 0 else (a0, a1), end


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--quick", action="store_true", help="fewer bounces")
    parser.add_argument("--B", type=float, default=0.8, help="the field (r_c = 1/B at speed 1, q = m = 1)")
    parser.add_argument("--output", default="magnetic.png")
    args = parser.parse_args()

    scene = bk.Scene(SCENE, set={"B": args.B}, particles=2)
    omega_c = args.B  # Omega = qB/m with q = m = 1
    traj = bk.trajectory(scene, collisions=25 if args.quick else 80)
    t, x, v = traj["times"], traj["positions"], traj["velocities"]
    print(f"B = {args.B:g}: r_c = {math.hypot(*v[0]) / omega_c:.4g}, {len(t) - 1} bounces, "
          f"speed {math.hypot(*v[0]):.15g} -> {math.hypot(*v[-1]):.15g}")

    fig, ax = plt.subplots(figsize=(7, 4))
    bk.plot_shape(scene.shape, ax=ax)
    for k in range(len(t) - 1):
        centre, radius, (lo, hi), end = arc_of(x[k], v[k], omega_c, t[k + 1] - t[k])
        # The closed-form arc must end where the toolkit found the next bounce.
        assert math.dist(end, x[k + 1]) < 1e-9, (k, end, x[k + 1])
        ax.add_patch(Arc(centre, 2 * radius, 2 * radius, theta1=math.degrees(lo), theta2=math.degrees(hi),
                         lw=0.8, color="C1"))
    ax.plot(x[:, 0], x[:, 1], ".", color="C3", ms=3)
    ax.set_aspect("equal")
    ax.set_title(f"stadium, B = {args.B:g}: cyclotron arcs between bounces")
    fig.savefig(args.output, dpi=100, bbox_inches="tight")
    print(f"wrote {args.output}")


if __name__ == "__main__":
    main()
