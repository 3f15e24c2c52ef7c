"""billiardkit: exact geometry of 2-D tables and 3-D regions, deterministic ensembles of driven
particles, and the energy-diffusion theory of Hodson & Jarzynski -- the library behind the
`billiard` program, with the same numbers for the same scene and seed.

    import billiardkit as bk
    scene = bk.Scene("scenes/clover-driven.yaml", particles=2000, time=10)
    res = bk.run(scene)                    # a RunResult: numpy arrays and a summary
    res.summary.var_dE, res.summary.se_var_dE, res.prediction["g2"] * scene.time
    bk.plot_run(res)

Shapes and scenes come from files, from dicts with the files' keys, and (scenes) from a Shape
plus keyword arguments; see docs/python.md.
"""
from . import _core
from ._core import (InputError, Scene, Shape, Shape3, boundary_map, chaos, coefficients, escape,
                    fokker_planck_cdf, fokker_planck_eta, fokker_planck_moments, fokker_planck_numerical, info,
                    lyapunov, sample_moments)
from .plotting import plot_run, plot_shape, plot_trajectory
from .results import RunResult, Summary, run
from .scenes import load_scene, load_shape
from .trajectories import Animation, animate, trajectory

__version__ = _core.__version__

__all__ = ["Animation", "InputError", "RunResult", "Scene", "Shape", "Shape3", "Summary", "animate", "boundary_map",
           "chaos", "coefficients", "escape", "fokker_planck_cdf", "fokker_planck_eta", "fokker_planck_moments",
           "fokker_planck_numerical", "info", "load_scene", "load_shape", "lyapunov", "plot_run", "plot_shape",
           "plot_trajectory", "run", "sample_moments", "trajectory", "__version__"]
