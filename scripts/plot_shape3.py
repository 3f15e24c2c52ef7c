#!/usr/bin/python3
"""Draws a 3-D shape (and a trajectory) from the JSON written by `billiard plot`.

    plot_shape3.py INPUT.json OUTPUT.png

INPUT.json: {"dimension": 3, "title": str, "faces": [[[x, y, z], ...], ...] (the wall's
polygons; a large mesh's triangles thinned by `billiard plot`), "spheres": [{"center": [x, y, z],
"radius": r, "outer": bool}], "trajectory": [[x, y, z], ...] (start, then collision points)}.
Four panels: a perspective view and the projections on the xy, xz and yz planes.
"""
import json
import sys

try:
    import matplotlib
except ImportError:
    sys.exit("plot_shape3.py: matplotlib is missing (Debian: apt install python3-matplotlib)")
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from mpl_toolkits.mplot3d.art3d import Poly3DCollection  # noqa: E402

FILL, WALL, BALL, PATH = "#dce8f3", "#1f3b57", "#8e9fb0", "#c0392b"


def sphere_mesh(center, radius, n=24):
    u, v = np.meshgrid(np.linspace(0, 2 * np.pi, n), np.linspace(0, np.pi, n // 2))
    return (center[0] + radius * np.cos(u) * np.sin(v), center[1] + radius * np.sin(u) * np.sin(v),
            center[2] + radius * np.cos(v))


def perspective(ax, data):
    faces = data["faces"]
    if faces:
        thin = len(faces) > 2000  # a mesh: no edges, or the picture is all edge
        ax.add_collection3d(Poly3DCollection(faces, facecolor=BALL if thin else FILL,
                                             edgecolor="none" if thin else WALL, linewidths=0.4,
                                             alpha=0.12 if thin else 0.25))
    for s in data["spheres"]:
        ax.plot_wireframe(*sphere_mesh(s["center"], s["radius"]), color=WALL if s["outer"] else BALL,
                          lw=0.3, alpha=0.5)
    path = np.array(data["trajectory"])
    if len(path):
        ax.plot(path[:, 0], path[:, 1], path[:, 2], "-", color=PATH, lw=0.7, alpha=0.8)
    points = [p for f in faces for p in f] + [p for p in data["trajectory"]]
    for s in data["spheres"]:
        points += [[c - s["radius"] for c in s["center"]], [c + s["radius"] for c in s["center"]]]
    lo, hi = np.min(points, axis=0), np.max(points, axis=0)
    half, mid = (hi - lo).max() / 2, (hi + lo) / 2
    ax.set_xlim(mid[0] - half, mid[0] + half)
    ax.set_ylim(mid[1] - half, mid[1] + half)
    ax.set_zlim(mid[2] - half, mid[2] + half)
    ax.set_box_aspect((1, 1, 1))
    if len(path):
        ax.plot(path[:1, 0], path[:1, 1], path[:1, 2], "o", color=PATH, ms=5)
    for axis, name in ((ax.xaxis, "x"), (ax.yaxis, "y"), (ax.zaxis, "z")):  # labels clear of the ticks
        axis.set_label_text(name)
        axis.labelpad = 10
    ax.tick_params(labelsize=7)


def projection(ax, data, i, j):
    for face in data["faces"]:
        f = np.array(face + [face[0]])
        ax.plot(f[:, i], f[:, j], "-", color=WALL, lw=0.3, alpha=0.25 if len(data["faces"]) > 2000 else 0.7)
    for s in data["spheres"]:
        ax.add_patch(plt.Circle((s["center"][i], s["center"][j]), s["radius"], fill=False,
                                color=WALL if s["outer"] else BALL, lw=1))
    path = np.array(data["trajectory"])
    if len(path):
        ax.plot(path[:, i], path[:, j], "-", color=PATH, lw=0.6, alpha=0.7)
        ax.plot(path[:1, i], path[:1, j], "o", color=PATH, mec="white", mew=1, ms=6, label="trajectory's start")
        ax.legend(fontsize=7, loc="upper right", framealpha=0.9)
    ax.set_title(f"projection on the {'xyz'[i]}{'xyz'[j]} plane", fontsize=9)
    ax.set_aspect("equal")
    ax.autoscale_view()
    ax.set_xlabel("xyz"[i])
    ax.set_ylabel("xyz"[j])


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    with open(sys.argv[1]) as f:
        data = json.load(f)
    fig = plt.figure(figsize=(10, 9))
    perspective(fig.add_subplot(2, 2, 1, projection="3d"), data)
    for k, (i, j) in enumerate(((0, 1), (0, 2), (1, 2))):
        projection(fig.add_subplot(2, 2, k + 2), data, i, j)
    fig.suptitle(data["title"], fontsize=10)
    fig.tight_layout()
    fig.savefig(sys.argv[2], dpi=110)  # the format is the extension's: png, pdf or svg


if __name__ == "__main__":
    main()
