"""Animations of a 2-D scene's particles: the table, the particles at each frame (their states at
uniform times, computed by the C++ core along their true flights), an optional trail, and for a
driven scene a side panel with the energy histogram against the Fokker-Planck density.

This file needs only numpy and matplotlib (no billiardkit._core), so that `billiard animate`
(scripts/plot_animate.py) draws with the same code as billiardkit.animate.  MP4 is written by
ffmpeg (matplotlib's FFMpegWriter), GIF by Pillow (or ffmpeg when Pillow is missing).  The movie
is written to a temporary name beside `output` and renamed into place when complete.
"""
import importlib.util
import os

import numpy as np

FILL, WALL, PARTICLE = "#dce8f3", "#1f3b57", "#d62728"
FORMATS = (".mp4", ".gif")
DPI = 100


def _region(ax, outline):
    """The table: the outer loop filled, the holes cut out (even-odd), the walls drawn."""
    from matplotlib.patches import PathPatch
    from matplotlib.path import Path
    vertices, codes = [], []
    for loop in outline:
        loop = np.asarray(loop, dtype=float)
        vertices += [*loop, loop[0]]
        codes += [Path.MOVETO] + [Path.LINETO] * (len(loop) - 1) + [Path.CLOSEPOLY]
    ax.add_patch(PathPatch(Path(vertices, codes), facecolor=FILL, edgecolor=WALL, lw=1.2))
    everything = np.concatenate([np.asarray(loop, dtype=float) for loop in outline])
    lo, hi = everything.min(axis=0), everything.max(axis=0)
    pad = 0.04 * (hi - lo).max()
    ax.set_xlim(lo[0] - pad, hi[0] + pad)
    ax.set_ylim(lo[1] - pad, hi[1] + pad)
    ax.set_aspect("equal")
    ax.set_xticks([])
    ax.set_yticks([])


def has_histogram(frames, histogram=None):
    """Is the side panel drawn?  histogram=None: when the frames carry a Fokker-Planck density."""
    fp = frames.get("fp_density") is not None
    if histogram and not fp:
        raise ValueError("the energy histogram needs a driven scene the theory covers (a Fokker-Planck density)")
    return fp if histogram is None else bool(histogram)


def figure(outline, frames, histogram=None, size=5.0):
    """The figure of the movie and its artists: (fig, table axes, histogram axes or None).  The
    figure is size x size inches at DPI dots per inch (twice as wide with the histogram), so
    every frame has the same even number of pixels, as H.264 needs."""
    from matplotlib.figure import Figure
    side = has_histogram(frames, histogram)
    fig = Figure(figsize=(2 * size if side else size, size), dpi=DPI)
    ax = fig.add_axes([0.02, 0.02, 0.46 if side else 0.96, 0.9])
    _region(ax, outline)
    hist_ax = fig.add_axes([0.58, 0.12, 0.39, 0.78]) if side else None
    return fig, ax, hist_ax


class _Painter:
    """Draws frame k: particles, trails, the histogram."""

    def __init__(self, fig, ax, hist_ax, frames, trail, title, marker_size):
        self.frames, self.trail, self.title = frames, trail, title
        self.x = np.asarray(frames["positions"], dtype=float)
        self.E = np.asarray(frames["energies"], dtype=float)
        self.times = np.asarray(frames["times"], dtype=float)
        self.fig, self.ax, self.hist_ax = fig, ax, hist_ax
        self.dots = ax.scatter(self.x[0, :, 0], self.x[0, :, 1], s=marker_size, c=PARTICLE, linewidths=0, zorder=3)
        self.trails = []
        if trail > 0:
            from matplotlib.collections import LineCollection
            self.trails = LineCollection([], colors=PARTICLE, linewidths=0.6, alpha=0.45, zorder=2)
            ax.add_collection(self.trails)
        self.heading = fig.suptitle("")
        if hist_ax is not None:
            finite = self.E[np.isfinite(self.E)]
            e_fp = np.asarray(frames["fp_energies"], dtype=float)
            density = np.asarray(frames["fp_density"], dtype=float)
            # Up to where the last density has fallen below 1e-3 of its peak, or the highest energies.
            tail = e_fp[density[-1] > 1e-3 * density[-1].max()]
            top = max(np.quantile(finite, 0.999) if finite.size else 0, tail.max() if tail.size else 0)
            self.bins = np.linspace(0, 1.05 * top, 40)
            self.e_fp, self.density = e_fp, density
            self._histogram_axes(hist_ax)

    def _histogram_axes(self, ax):
        """The panel's artists, made once and updated frame by frame (a new histogram drawn each
        frame costs several times the rest of the frame): the bars and the density's line."""
        self.counts = [self._histogram(k) for k in range(len(self.times))]
        self.bars = ax.bar(self.bins[:-1], self.counts[0], width=np.diff(self.bins), align="edge", color="#7aa6d6",
                           label=f"simulation, N = {self.E.shape[1]}")
        (self.curve,) = ax.plot([], [], color="k", lw=1.2, label="Fokker–Planck")
        ax.set_xlim(self.bins[0], self.bins[-1])
        ax.set_xlabel("energy E")
        ax.set_ylabel("density")
        ax.legend(loc="upper right", fontsize=8)

    def _histogram(self, k):
        E = self.E[k][np.isfinite(self.E[k])]
        counts, _ = np.histogram(E, bins=self.bins, density=E.size > 0)
        return counts.astype(float)

    def __call__(self, k):
        x = self.x[k]
        self.dots.set_offsets(x)
        if self.trail > 0:
            first = max(0, k - self.trail)
            self.trails.set_segments([self.x[first:k + 1, i] for i in range(x.shape[0])])
        self.heading.set_text(f"{self.title}   t = {self.times[k]:.4g}")
        if self.hist_ax is not None:
            for bar, height in zip(self.bars, self.counts[k]):
                bar.set_height(height)
            top = self.counts[k].max()
            if k > 0:
                self.curve.set_data(self.e_fp, self.density[k - 1])
                top = max(top, self.density[k - 1].max())
            self.hist_ax.set_ylim(0, 1.1 * top if top > 0 else 1)


def _writer(output, fps):
    from matplotlib import animation
    ext = os.path.splitext(output)[1].lower()
    if ext == ".gif" and importlib.util.find_spec("PIL") is not None:
        return animation.PillowWriter(fps=fps)
    if not animation.FFMpegWriter.isAvailable():
        raise RuntimeError(f"writing {ext} needs ffmpeg (Debian: apt install ffmpeg)")
    if ext == ".gif":
        return animation.FFMpegWriter(fps=fps, codec="gif")
    return animation.FFMpegWriter(fps=fps, codec="h264", extra_args=["-pix_fmt", "yuv420p"])


def write_movie(outline, frames, output, *, fps=25, trail=0, histogram=None, title="", marker_size=9.0,
                progress=None):
    """Writes the movie of `frames` (a dict: times (K,), positions (K, N, 2), energies (K, N), and
    fp_energies, fp_density or None) over the table `outline` (closed polylines, outer first) to
    `output` (.mp4 or .gif), one frame per sample time.  trail: frames of trail behind each
    particle (0: none).  progress(done, total) is called after each frame."""
    output = os.fspath(output)
    ext = os.path.splitext(output)[1].lower()
    if ext not in FORMATS:
        raise ValueError(f"{output}: the movie's format follows its extension: .mp4 or .gif")
    if not fps > 0:
        raise ValueError("fps must be positive")
    import matplotlib
    matplotlib.use("Agg")
    fig, ax, hist_ax = figure(outline, frames, histogram)
    paint = _Painter(fig, ax, hist_ax, frames, int(trail), title, marker_size)
    tmp = f"{output}.tmp-{os.getpid()}{ext}"
    writer = _writer(output, fps)
    total = len(frames["times"])
    try:
        with writer.saving(fig, tmp, DPI):
            for k in range(total):
                paint(k)
                writer.grab_frame()
                if progress:
                    progress(k + 1, total)
        os.replace(tmp, output)
    finally:
        if os.path.exists(tmp):
            os.remove(tmp)
    return output
