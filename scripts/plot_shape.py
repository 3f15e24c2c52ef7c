#!/usr/bin/python3
"""Draws a shape (and a trajectory) from the JSON written by `billiard plot`.

    plot_shape.py INPUT.json OUTPUT.png|OUTPUT.pdf|OUTPUT.svg

INPUT.json: {"title": str, "loops": [[[x, y], ...], ...] (outer boundary first, then the
holes, each a closed polyline without its repeated first point), "trajectory": [[x, y], ...]
(start point, then the collision points; may be empty)}.
"""
import json
import sys

try:
    import matplotlib
except ImportError:
    sys.exit("plot_shape.py: matplotlib is missing (Debian: apt install python3-matplotlib)")
matplotlib.use("Agg")
# Long trajectories are one path of 10^5-10^6 points: Agg draws it in chunks or overflows.
matplotlib.rcParams["agg.path.chunksize"] = 10000
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.patches import PathPatch  # noqa: E402
from matplotlib.path import Path  # noqa: E402

FILL, WALL, PATH = "#dce8f3", "#1f3b57", "#c0392b"
# Above this many collisions the bounce points would only clutter the picture.
MAX_MARKED_BOUNCES = 200


def region_patch(loops):
    """One compound path: the outer loop runs counter-clockwise and the holes clockwise, so
    the fill leaves the holes empty (white) under either fill rule."""
    vertices, codes = [], []
    for loop in loops:
        vertices += loop + [loop[0]]
        codes += [Path.MOVETO] + [Path.LINETO] * (len(loop) - 1) + [Path.CLOSEPOLY]
    return PathPatch(Path(vertices, codes), facecolor=FILL, edgecolor=WALL, lw=1.6,
                     joinstyle="round", zorder=1)


def draw_trajectory(ax, points):
    xs, ys = zip(*points)
    bounces = len(points) - 1
    # Long trajectories get thinner, fainter lines, so that they show where the particle
    # goes often instead of one solid blot.
    lw = 0.9 if bounces <= MAX_MARKED_BOUNCES else 0.5
    alpha = min(0.75, max(0.2, 150 / bounces))
    ax.plot(xs, ys, "-", color=PATH, lw=lw, alpha=alpha, zorder=2)
    if bounces <= MAX_MARKED_BOUNCES:
        ax.plot(xs[1:], ys[1:], "o", color=PATH, ms=2.2, zorder=3)
    ax.plot(xs[:1], ys[:1], "o", color=PATH, mec="white", mew=1, ms=7, zorder=4, label="start")
    ax.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0), frameon=False)


def figure_for(loops):
    """A figure with the shape's aspect ratio, 6.5 inches along its longer side."""
    xs = [x for x, _ in loops[0]]
    ys = [y for _, y in loops[0]]
    aspect = (max(ys) - min(ys)) / (max(xs) - min(xs))
    width = 6.5 if aspect <= 1 else max(3.5, 6.5 / aspect)
    return plt.subplots(figsize=(width, width * aspect + 0.6))


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    with open(sys.argv[1]) as f:
        data = json.load(f)
    fig, ax = figure_for(data["loops"])
    ax.add_patch(region_patch(data["loops"]))
    if data["trajectory"]:
        draw_trajectory(ax, data["trajectory"])
    ax.set_aspect("equal")
    ax.autoscale_view()
    ax.margins(0.04)
    ax.tick_params(labelsize=8, colors="#555555")
    ax.set_xlabel("x (length units of the shape file)", fontsize=8)
    ax.set_ylabel("y", fontsize=8)
    for side in ax.spines.values():
        side.set_color("#bbbbbb")
    ax.set_title(data["title"], fontsize=10)
    output = sys.argv[2]
    ext = output.rsplit(".", 1)[-1].lower()  # `billiard plot` allows png, pdf and svg
    try:
        # Cropped to the drawing: the figure size only sets the scale.
        fig.savefig(output, dpi=150, format=ext, bbox_inches="tight", pad_inches=0.1)
    except OSError as e:
        sys.exit(f"plot_shape.py: cannot write {sys.argv[2]}: {e.strerror}")


if __name__ == "__main__":
    main()
