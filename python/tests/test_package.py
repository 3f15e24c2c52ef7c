"""The package's objects against the `billiard` program and against each other: version, Scene
from a Shape, numpy initial conditions, RunResult and its Summary, progress, Ctrl-C, plots."""
import json
import math
import pathlib
import subprocess
import sys
import types

import numpy as np
import pytest

import billiardkit as bk
from conftest import billiard, interrupted

CLOVER_DRIVE = {"periodic": {"amplitude": ["10/sqrt(2)", "10/sqrt(2)"], "omega": "40*pi", "phase": 0}}

def test_version_is_the_programs():
    assert billiard("--version").split() == ["billiard", bk.__version__]

def test_summary_equals_the_programs_summary_json(source, tmp_path):
    scene_file = source / "scenes" / "clover-driven.yaml"
    billiard("run", scene_file, "--particles", 300, "--time", 4, "--quiet", "--no-csv", "--out", tmp_path)
    cli = json.loads((tmp_path / "summary.json").read_text())
    res = bk.run(bk.Scene(scene_file, particles=300, time=4), progress=False)
    for key in ("mean_dE", "var_dE", "se_mean_dE", "se_var_dE", "mean_dE_deviation_se", "var_dE_deviation_se",
                "fp_mean_dE", "fp_var_dE", "mean_dE_fp_deviation_se", "var_dE_fp_deviation_se"):
        assert getattr(res.summary, key) == getattr(res, key) == cli[key], key
    with pytest.raises(AttributeError, match="no_such_key"):
        res.no_such_key
    for s, c in zip(res.summaries, cli["per_time"]):
        assert (s.t, s.var_dE, s.se_var_dE) == (c["t"], c["var_dE"], c["se_var_dE"])
    d = json.loads(json.dumps(res.to_dict()))  # plain data
    assert d["var_dE"] == cli["var_dE"] and d["collisions"] == res.collisions.tolist()
    assert res["energies"] is res.energies

def test_scene_from_a_shape_is_the_scene_file(source):
    """The driven clover built from a Shape and keyword arguments runs the same particles as
    scenes/clover-driven.yaml (same initial states, same numbers)."""
    shape = bk.load_shape(source / "shapes" / "clover.yaml")
    built = bk.Scene(shape, force=CLOVER_DRIVE, energy=0.5, particles=64, time=3, record=1)
    from_file = bk.Scene(source / "scenes" / "clover-driven.yaml", particles=64, time=3)
    assert np.array_equal(built.record_times, from_file.record_times)
    assert bk.run(built).energies.tobytes() == bk.run(from_file).energies.tobytes()
    # A Shape where a scene dict names its shape file; a dict-built shape too.
    with_dict = bk.Scene({"shape": shape, "initial": {"microcanonical": {"energy": 0.5}}, "force": CLOVER_DRIVE,
                          "run": {"time": 3, "particles": 64, "record": {"every": 1}}})
    assert bk.run(with_dict).energies.tobytes() == bk.run(from_file).energies.tobytes()
    disk = bk.load_shape({"parameters": {"R": 2}, "boundary": {"circle": {"center": [0, 0], "radius": "R"}}})
    assert bk.Scene(disk, energy=1, time=1, particles=3).shape.info()["V"] == pytest.approx(4 * math.pi, rel=1e-15)

def test_overridden_shape_parameters_reach_the_scene(source):
    shape = bk.load_shape(source / "shapes" / "clover.yaml", set={"R2": 3})
    scene = bk.Scene(shape, energy=0.5, time=1, particles=2)
    assert scene.shape.parameters == shape.parameters and scene.shape.info()["V"] == shape.info()["V"]

def test_numpy_initial_conditions(source):
    """Arrays of positions and velocities are the particles' initial states: a free square run
    keeps each particle's energy |v|^2/2 at the record times 0, 1, 2 and 5."""
    square = bk.load_shape(source / "shapes" / "square.yaml")
    x = np.array([[0.5, 0.5], [0.25, 0.75], [0.1, 0.2]])
    v = np.array([[1.0, 0.0], [0.3, -0.4], [-2.0, 1.5]])
    res = bk.run(bk.Scene(square, positions=x, velocities=v, time=5, record=[1, 2]))
    assert res.energies.shape == (3, 4)
    assert np.allclose(res.energies, 0.5 * (v**2).sum(axis=1)[:, None], rtol=1e-14, atol=0)
    with pytest.raises(ValueError, match="positions and velocities"):
        bk.Scene(square, positions=x, velocities=v[:2], time=1)
    with pytest.raises(bk.InputError):
        bk.Scene(square, positions=x + 5, velocities=v, time=1)  # outside the table

def test_progress_reaches_every_particle_and_changes_nothing(source, monkeypatch):
    bars = []

    class Bar:
        def __init__(self, total, **kwargs):
            self.total, self.n = total, 0
            bars.append(self)

        def update(self, k):
            self.n += k

        def __enter__(self):
            return self

        def __exit__(self, *exc):
            return False

    monkeypatch.setitem(sys.modules, "tqdm", types.ModuleType("tqdm"))
    monkeypatch.setitem(sys.modules, "tqdm.auto", types.SimpleNamespace(tqdm=Bar))
    scene = bk.Scene(source / "scenes" / "clover-driven.yaml", particles=500, time=2)
    shown = bk.run(scene, progress=True)
    assert len(bars) == 1 and bars[0].n == bars[0].total == 500
    assert shown.energies.tobytes() == bk.run(scene, progress=False).energies.tobytes()

def test_ctrl_c_interrupts_a_long_run(source):
    """SIGINT during a run that would take minutes raises KeyboardInterrupt (between chunks of
    particles of about a quarter second)."""
    script = ("import billiardkit as bk, sys\n"
              f"scene = bk.Scene({str(source / 'scenes' / 'clover-driven.yaml')!r}, particles=10**7, time=20)\n"
              "print('started', flush=True)\n"
              "try:\n    bk.run(scene, threads=1, progress=False)\n"
              "except KeyboardInterrupt:\n    print('interrupted', flush=True); sys.exit(3)\n")
    assert interrupted(script) == (3, "interrupted\n")

def test_plots_draw_the_objects(source):
    import matplotlib
    matplotlib.use("Agg")
    shape = bk.load_shape(source / "shapes" / "annulus.yaml")
    ax = bk.plot_shape(shape)
    loops = shape.outline()
    assert len(ax.lines) == len(loops) and np.array_equal(ax.lines[0].get_xydata(), loops[0])
    assert shape.plot() is not None and shape._repr_png_()[:8] == b"\x89PNG\r\n\x1a\n"
    traj = bk.trajectory(shape, collisions=20)
    ax = bk.plot_trajectory(traj, shape)
    assert np.array_equal(ax.lines[-1].get_xydata(), traj["positions"])
    res = bk.run(bk.Scene(source / "scenes" / "clover-driven.yaml", particles=50, time=2))
    ax = bk.plot_run(res)
    assert [line.get_label() for line in ax.lines if not line.get_label().startswith("_")] == ["g2 t", "g1 t"]
    assert res._repr_png_()[:4] == b"\x89PNG" and "<table>" in res._repr_html_()
    sphere = bk.load_shape(source / "shapes" / "3d" / "sinai3.yaml")
    assert sphere._repr_png_()[:4] == b"\x89PNG"

@pytest.mark.parametrize("script", ["own_table.py", "driven_ensemble.py", "paper_fig2.py", "paper_fig4.py",
                                    "magnetic_trajectory.py"])
def test_examples_run(source, tmp_path, script):
    done = subprocess.run([sys.executable, str(source / "examples" / script), "--quick", "--output",
                           str(tmp_path / "out.png")], capture_output=True, text=True, cwd=tmp_path)
    assert done.returncode == 0, done.stderr
    assert (tmp_path / "out.png").read_bytes()[:4] == b"\x89PNG"


def test_the_type_stubs_name_everything_public():
    """__init__.pyi (shipped for editors) declares every name in __all__, every public attribute of
    each class, and each Python function's parameters with their defaults."""
    import ast
    import inspect
    stub = ast.parse((pathlib.Path(bk.__file__).parent / "__init__.pyi").read_text())
    top = {n.name: n for n in stub.body if isinstance(n, (ast.FunctionDef, ast.ClassDef))}
    top.update({t.id: n for n in stub.body if isinstance(n, (ast.Assign, ast.AnnAssign))
                for t in (n.targets if isinstance(n, ast.Assign) else [n.target])})
    assert sorted(set(bk.__all__) - set(top)) == []

    def members(cls_node):
        names = set()
        for base in cls_node.bases:
            if isinstance(base, ast.Name) and base.id in top:
                names |= members(top[base.id])
        for n in cls_node.body:
            if isinstance(n, (ast.FunctionDef, ast.ClassDef)):
                names.add(n.name)
            elif isinstance(n, ast.AnnAssign):
                names.add(n.target.id)
        return names

    for name in bk.__all__:
        obj = getattr(bk, name)
        if isinstance(top[name], ast.ClassDef) and not issubclass(obj, BaseException):
            public = {a for a in dir(obj) if not a.startswith("_")}
            assert sorted(public - members(top[name])) == [], name
        elif isinstance(top[name], ast.FunctionDef) and inspect.isfunction(obj):
            args = top[name].args
            stubbed = [a.arg for a in args.posonlyargs + args.args + args.kwonlyargs]
            assert stubbed == [p.name for p in inspect.signature(obj).parameters.values()
                               if p.kind not in (p.VAR_KEYWORD, p.VAR_POSITIONAL)], name
