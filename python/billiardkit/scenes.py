"""Shapes and scenes: what the compiled core reads (files and dicts), plus scenes built from a
Shape object and keyword arguments, and initial conditions given as numpy arrays."""
import json
import os
import tempfile

import numpy as np

from . import _core


def load_shape(source, *, set=None, base_dir=None, name="shape dict"):
    """Reads and validates a shape: a Shape (2-D), or a Shape3 when the file or dict has
    `dimension: 3`.  source: a shape file's path or a dict with the file's keys; set: parameter
    overrides {NAME: value or expression}; base_dir: the folder a dict's `mesh:` file is relative to.
    Raises InputError (a ValueError) naming file, line and problem."""
    shape = _core.load_shape(source, set=set, base_dir=base_dir, name=name)
    # Where it came from, so that Scene(shape, ...) can name it in a scene.
    shape._source = dict(source) if isinstance(source, dict) else os.path.abspath(os.fspath(source))
    return shape


def _shape_file(shape, folder):
    """A shape file for `shape`: its own, or its dict written into `folder`."""
    source = getattr(shape, "_source", None) or os.path.abspath(shape.file)
    if isinstance(source, dict):
        path = os.path.join(folder, "shape.yaml")
        with open(path, "w") as f:
            json.dump(source, f, indent=1, default=lambda a: a.tolist())  # JSON is YAML
        return path
    return source


def _initial_csv(positions, velocities, dimension, folder):
    x, v = np.asarray(positions, dtype=float), np.asarray(velocities, dtype=float)
    if x.ndim != 2 or x.shape != v.shape or x.shape[1] != dimension:
        raise ValueError(f"positions and velocities must both be (N, {dimension}) arrays, "
                         f"got {x.shape} and {v.shape}")
    path = os.path.join(folder, "initial.csv")
    np.savetxt(path, np.hstack([x, v]), delimiter=",", fmt="%.17g")
    return path, len(x)


def scene_dict(shape, *, force=None, energy=None, positions=None, velocities=None, mass=1, time,
               record=None, particles=None, seed=1, folder):
    """The scene file's keys for `shape` and the keyword arguments of Scene (files it needs go
    into `folder`)."""
    d = {"shape": _shape_file(shape, folder), "mass": mass,
         "set": {k: f"{v:.17g}" for k, v in shape.parameters.items()},
         "run": {"time": time, "seed": seed}}
    if force:
        d["force"] = force
    if (positions is None) != (velocities is None):
        raise ValueError("give both positions and velocities, or neither")
    if positions is not None:
        csv, n = _initial_csv(positions, velocities, shape.dimension, folder)
        d["initial"] = {"csv": csv}
        d["run"]["particles"] = n if particles is None else particles
    elif energy is None:
        raise ValueError("give energy (a microcanonical start) or positions and velocities")
    else:
        d["initial"] = {"microcanonical": {"energy": energy}}
        d["run"]["particles"] = 1000 if particles is None else particles
    if record is not None:
        # As `billiard run --record`: 0 and the end time are added.
        d["run"]["record"] = [0.0, *(float(t) for t in record if t > 0)] if np.ndim(record) else {"every": record}
    return d


_core_scene_init = _core.Scene.__init__


def _scene_init(self, source, *, particles=None, time=None, omega=None, record=None, seed=None, set=None,
                base_dir=None, name="scene dict", **from_shape):
    with tempfile.TemporaryDirectory(prefix="billiardkit-") as folder:
        if isinstance(source, (_core.Shape, _core.Shape3)):
            if time is None:
                raise ValueError("a scene from a shape needs time=")
            source = scene_dict(source, particles=particles, time=time, record=record,
                                seed=1 if seed is None else seed, folder=folder, **from_shape)
            record = None
        elif from_shape:
            raise TypeError(f"{', '.join(from_shape)}: only for a scene built from a Shape")
        elif isinstance(source, dict) and isinstance(source.get("shape"), (_core.Shape, _core.Shape3)):
            source = dict(source, shape=_shape_file(source["shape"], folder))
        _core_scene_init(self, source, particles=particles, time=time, omega=omega, record=record, seed=seed,
                         set=set, base_dir=base_dir, name=name)


_scene_init.__doc__ = """Scene(source, *, particles=None, time=None, omega=None, record=None, seed=None, set=None,
      base_dir=None, name="scene dict", **from_shape)

source: a scene file's path; a dict with the file's keys (its `shape` may be a Shape object);
or a Shape, with keyword arguments:
    force: the scene file's `force` block, e.g. {"periodic": {"amplitude": [1, 0], "omega": 100}}
    energy: a microcanonical start at this energy, or
    positions, velocities: (N, d) arrays of initial conditions
    mass (1), time (required), record (a step or a list of times), particles, seed.
particles, time, omega, record, seed, set: the overrides of `billiard run`.
Raises InputError naming file, line and problem."""
_core.Scene.__init__ = _scene_init


def load_scene(source, **kwargs):
    """Same as Scene(source, **kwargs)."""
    return _core.Scene(source, **kwargs)
