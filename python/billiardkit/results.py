"""Ensemble runs as objects: RunResult (numpy arrays, a Summary per record time) and run(), which
shows progress with tqdm when it is installed and stops on Ctrl-C."""
import math
import sys

import numpy as np

from . import _core


def _in_se(difference, se):
    """A deviation in standard errors; NaN when the sample has none (no particle has collided)."""
    return difference / se if se > 0 else math.nan


class Summary:
    """The energy change dE = E(t) - E(0) of the particles that did not escape, at one record
    time t: mean_dE, var_dE and their standard errors se_mean_dE, se_var_dE (the numbers of
    `billiard run`'s summary.json); with a prediction, predicted_mean_dE = g1 t,
    predicted_var_dE = g2 t and the deviations from them in standard errors; with the closed
    forms, fp_mean_dE, fp_var_dE (the exact Fokker-Planck moments) and their deviations."""

    def __init__(self, t, dE, prediction=None, energy=0.0):
        self.t = float(t)
        self.particles = len(dE)
        self.mean_dE, self.var_dE, self.se_mean_dE, self.se_var_dE = _core.sample_moments(dE)
        if prediction and self.t > 0:
            self.predicted_mean_dE = prediction["g1"] * self.t
            self.predicted_var_dE = prediction["g2"] * self.t
            self.mean_dE_deviation_se = _in_se(self.mean_dE - self.predicted_mean_dE, self.se_mean_dE)
            self.var_dE_deviation_se = _in_se(self.var_dE - self.predicted_var_dE, self.se_var_dE)
        if prediction and prediction.get("C") is not None and self.t > 0:
            fp = _core.fokker_planck_moments(prediction["C"] * self.t, energy, prediction["dimension"])
            self.fp_mean_dE, self.fp_var_dE = fp["mean"] - energy, fp["variance"]
            self.mean_dE_fp_deviation_se = _in_se(self.mean_dE - self.fp_mean_dE, self.se_mean_dE)
            self.var_dE_fp_deviation_se = _in_se(self.var_dE - self.fp_var_dE, self.se_var_dE)

    def to_dict(self):
        return dict(vars(self))

    def __repr__(self):
        return (f"Summary(t={self.t:g}: <dE> = {self.mean_dE:.6g} ± {self.se_mean_dE:.2g}, "
                f"Var(dE) = {self.var_dE:.6g} ± {self.se_var_dE:.2g}, {self.particles} particles)")


class RunResult:
    """An ensemble run: record_times (m,), energies (N, m) (NaN after an escape), collisions (N,),
    escaped (N,), seconds, collisions_per_second, threads, prediction (the coefficients of
    `billiard coeffs`, or None), scene; summary (a Summary at the end time) and
    summaries (one per record time).  res["energies"] is res.energies; the summary's values are
    the run's attributes too (res.var_dE, res.se_var_dE, ...)."""

    _fields = ("record_times", "energies", "collisions", "escaped", "seconds", "collisions_per_second", "threads",
               "prediction")

    def __init__(self, scene, raw):
        self.scene = scene
        for key in self._fields:
            setattr(self, key, raw[key])
        self.summaries = []
        E = self.energies[~self.escaped]
        for k, t in enumerate(self.record_times):
            self.summaries.append(Summary(t, E[:, k] - E[:, 0], self.prediction, scene.energy))
        self.summary = self.summaries[-1]

    def __getattr__(self, name):
        """The end time's summary as the run's own attributes: res.var_dE is res.summary.var_dE."""
        summary = self.__dict__.get("summary")
        if summary is None or name.startswith("_") or not hasattr(summary, name):
            raise AttributeError(f"'RunResult' object has no attribute '{name}'")
        return getattr(summary, name)

    def __getitem__(self, key):
        if key not in self._fields:
            raise KeyError(key)
        return getattr(self, key)

    def to_dict(self):
        """Plain Python data (lists, numbers): the keys of `billiard run`'s summary.json that a run
        in Python has, with per_time, plus the arrays as lists."""
        d = {k: getattr(self, k) for k in self._fields}
        d = {k: v.tolist() if isinstance(v, np.ndarray) else v for k, v in d.items()}
        d.update(self.summary.to_dict())
        d.pop("t")
        d.update(particles=len(self.energies), escapes=int(self.escaped.sum()),
                 per_time=[s.to_dict() for s in self.summaries], scene=self.scene.file)
        return d

    def __repr__(self):
        return (f"<billiardkit.RunResult: {len(self.energies)} particles, t = 0 .. {self.record_times[-1]:g}, "
                f"{int(self.collisions.sum())} collisions, {self.summary!r}>")

    def _repr_html_(self):
        rows = "".join(f"<tr><td>{s.t:g}</td><td>{s.mean_dE:.6g} ± {s.se_mean_dE:.2g}</td>"
                       f"<td>{s.var_dE:.6g} ± {s.se_var_dE:.2g}</td></tr>" for s in self.summaries)
        return (f"<p>{len(self.energies)} particles in <code>{self.scene.file}</code>, "
                f"{int(self.collisions.sum())} collisions, {int(self.escaped.sum())} escapes</p>"
                f"<table><tr><th>t</th><th>&lt;dE&gt;</th><th>Var(dE)</th></tr>{rows}</table>")

    def _repr_png_(self):
        from .plotting import png_of, plot_run
        return png_of(plot_run, self)

    def plot(self, ax=None):
        from .plotting import plot_run
        return plot_run(self, ax=ax)


def _progress_bar(total, enabled, unit="particle", desc="run"):
    """A tqdm bar when enabled (None: on a terminal or in Jupyter) and tqdm is installed; otherwise nothing."""
    if enabled is None:
        enabled = sys.stderr.isatty() or "ipykernel" in sys.modules
    if not enabled:
        return None
    try:
        from tqdm.auto import tqdm
    except ImportError:
        return None
    return tqdm(total=total, unit=unit, desc=desc)


def run(scene, *, threads=0, verify=False, progress=None):
    """Runs the scene's ensemble, as `billiard run` does (same numbers for the same scene and seed,
    for any number of threads), with the GIL released, and returns a RunResult.

    threads: OpenMP threads (0: all cores).  verify: also check the midpoint of every free flight.
    progress: True for a tqdm bar, False for none, None for a bar when stderr is a terminal (or in
    Jupyter) and tqdm is installed.  Ctrl-C raises KeyboardInterrupt within about a second."""
    bar = _progress_bar(scene.particles, progress)
    if bar is None:
        return RunResult(scene, _core.run(scene, threads=threads, verify=verify))
    with bar:
        update = lambda done, total: bar.update(done - bar.n)  # noqa: E731
        return RunResult(scene, _core.run(scene, threads=threads, verify=verify, progress=update))


