"""Plotting helpers (matplotlib, imported when first used): each draws into `ax` (a new figure's
axes when None) and returns the axes.  Shapes, Shape3s and RunResults also draw themselves in
Jupyter (_repr_png_)."""
import io

import numpy as np

from . import _core


def _axes(ax, projection=None):
    if ax is not None:
        return ax
    import matplotlib.pyplot as plt
    fig = plt.figure(figsize=(5, 5))
    return fig.add_subplot(projection=projection)


def plot_shape(shape, ax=None, **style):
    """The boundary of a Shape (its outline: every loop, arcs finely sampled), or the walls of a
    Shape3 (its triangles and spheres, as wireframes)."""
    if isinstance(shape, _core.Shape3):
        return _plot_shape3(shape, ax)
    ax = _axes(ax)
    style = {"color": "k", "lw": 1.2, **style}
    for loop in shape.outline():
        ax.plot(loop[:, 0], loop[:, 1], **style)
    ax.set_aspect("equal")
    ax.set_title(shape.name)
    return ax


def _plot_shape3(shape, ax):
    ax = _axes(ax, projection="3d")
    vertices, triangles = shape.mesh()
    if len(triangles):
        ax.plot_trisurf(vertices[:, 0], vertices[:, 1], vertices[:, 2], triangles=triangles, alpha=0.15,
                        edgecolor="k", linewidth=0.2)
    u, v = np.meshgrid(np.linspace(0, 2 * np.pi, 24), np.linspace(0, np.pi, 12))
    for s in shape.spheres():
        c, r = s["center"], s["radius"]
        ax.plot_wireframe(c[0] + r * np.cos(u) * np.sin(v), c[1] + r * np.sin(u) * np.sin(v), c[2] + r * np.cos(v),
                          color="k", linewidth=0.3)
    ax.set_title(shape.name)
    return ax


def plot_trajectory(trajectory, shape=None, ax=None, **style):
    """A trajectory (the dict of billiardkit.trajectory) over the shape when given: its dense
    samples joined in order when it has them (trajectory(..., dt=...): a driven particle's curved
    flights), else its bounce points (straight segments: the path of a free particle)."""
    samples = trajectory.get("samples")
    x = trajectory["positions"] if samples is None else samples["positions"]
    if x.shape[1] == 3:
        ax = _axes(ax, projection="3d") if shape is None else plot_shape(shape, ax)
        ax.plot(x[:, 0], x[:, 1], x[:, 2], **{"lw": 0.6, **style})
        return ax
    ax = plot_shape(shape, _axes(ax)) if shape is not None else _axes(ax)
    ax.plot(x[:, 0], x[:, 1], **{"lw": 0.6, "color": "C0", **style})
    ax.set_aspect("equal")
    return ax


def plot_run(result, ax=None):
    """Var(dE) and <dE> of a RunResult against time, with their standard errors, and the theory's
    g1 t and g2 t when the scene has a prediction."""
    ax = _axes(ax)
    t = np.array([s.t for s in result.summaries])
    for name, label, color in (("var_dE", "Var(dE)", "C0"), ("mean_dE", "<dE>", "C1")):
        y = np.array([getattr(s, name) for s in result.summaries])
        se = np.array([getattr(s, "se_" + name) for s in result.summaries])
        ax.errorbar(t, y, yerr=se, fmt="o", ms=3, color=color, label=label)
    if result.prediction:
        ax.plot(t, result.prediction["g2"] * t, "-", color="C0", lw=1, label="g2 t")
        ax.plot(t, result.prediction["g1"] * t, "-", color="C1", lw=1, label="g1 t")
    ax.set_xlabel("t")
    ax.set_ylabel("energy change")
    ax.legend()
    return ax


def png_of(plot, obj):
    """PNG bytes of plot(obj) (for _repr_png_), or None without matplotlib."""
    try:
        import matplotlib
        from matplotlib.figure import Figure
    except ImportError:
        return None
    del matplotlib
    fig = Figure(figsize=(4, 4))
    plot(obj, ax=fig.add_subplot(projection="3d" if isinstance(obj, _core.Shape3) else None))
    buffer = io.BytesIO()
    fig.savefig(buffer, format="png", dpi=80, bbox_inches="tight")
    return buffer.getvalue()


def _shape_html(shape):
    i = shape.info()
    return (f"<b>{shape.name}</b> ({shape.dimension}-D): V = {i['V']:.6g}, S = {i['S']:.6g}, "
            f"mean free path = {i['mean_free_path']:.6g}, {i.get('holes', 0)} holes")


for _cls in (_core.Shape, _core.Shape3):
    _cls.plot = lambda self, ax=None: plot_shape(self, ax)
    _cls.plot.__doc__ = "Same as billiardkit.plot_shape(shape, ax)."
    _cls._repr_png_ = lambda self: png_of(plot_shape, self)
    _cls._repr_html_ = _shape_html
