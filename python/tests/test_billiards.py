"""The Python module against the `billiard` program and against closed forms."""
import json
import math
import os
import re
import subprocess
import sys
import threading
import time

import numpy as np
import pytest

import billiardkit as bk
from conftest import BINARY, billiard, billiard_json


# --- shapes --------------------------------------------------------------------------------

@pytest.mark.parametrize("shape,set_", [("clover", {}), ("sinai", {}), ("clover", {"R2": "3"}), ("stadium", {})])
def test_info_equals_cli(source, shape, set_):
    path = source / "shapes" / f"{shape}.yaml"
    sets = [a for k, v in set_.items() for a in ("--set", f"{k}={v}")]
    cli = billiard_json("info", path, *sets)
    py = bk.info(bk.load_shape(path, set=set_))
    for key in ("V", "S", "mean_free_path", "holes", "name", "parameters"):
        assert py[key] == cli[key], key
    assert np.array_equal(py["boundary_tensor"], np.array(cli["boundary_tensor"]))
    assert py["pieces"] == cli["pieces"]


def test_shape_from_dict_has_the_closed_form_measures():
    shape = bk.load_shape({"parameters": {"L": 2}, "boundary": {"polygon": [[0, 0], ["L", 0], ["L", 1], [0, 1]]},
                                  "holes": [{"circle": {"center": [1, 0.5], "radius": 0.25}}]})
    info = shape.info()
    V, S = 2 - math.pi / 16, 6 + math.pi / 2
    assert info["V"] == pytest.approx(V, rel=1e-14)
    assert info["S"] == pytest.approx(S, rel=1e-14)
    assert info["mean_free_path"] == pytest.approx(math.pi * V / S, rel=1e-14)
    # ∫ n nᵀ dS: the rectangle's walls give diag(2, 4), the circle adds (π r) I.
    assert info["boundary_tensor"] == pytest.approx(np.diag([2, 4]) + math.pi / 4 * np.eye(2), abs=1e-14)


def test_bad_dict_raises_with_the_message(source):
    with pytest.raises(bk.InputError, match=r"shape dict:\d+: .*radius"):
        bk.load_shape({"boundary": {"circle": {"center": [0, 0], "radius": -1}}})
    scene = clover_scene_dict()
    scene["force"] = {"periodc": {"amplitude": [1, 0], "omega": 100}}
    with pytest.raises(ValueError, match=r"scene dict:\d+: .*periodc"):
        bk.load_scene(scene, base_dir=source / "scenes")
    with pytest.raises(bk.InputError, match="cannot open"):
        bk.load_shape("no-such-shape.yaml")


def test_a_field_not_finite_in_the_box_raises_at_its_key(source, tmp_path):
    """As `billiard run`: sqrt(x - 0.5) is NaN on the left half of the square, reported at the
    line of `field` when the scene is loaded."""
    path = tmp_path / "scene.yaml"
    path.write_text(f"shape: {source / 'shapes' / 'square.yaml'}\nmass: 1\n"
                    "initial:\n  microcanonical: {energy: 1/2}\n"
                    "force:\n  field:\n    amplitude: ['sqrt(x - 0.5)', '0']\n    omega: 40*pi\n"
                    "run:\n  particles: 50\n  time: 1\n")
    with pytest.raises(ValueError, match=re.escape(f"{path}:6: the force is not finite at (x, y) = (0, 0), "
                                                   "in the table's bounding box")):
        bk.load_scene(path)


# --- theory --------------------------------------------------------------------------------

@pytest.mark.parametrize("omega", [None, "320*pi"])
def test_coefficients_equal_cli(source, omega):
    scene_file = source / "scenes" / "clover-driven.yaml"
    cli = billiard_json("coeffs", scene_file, *(["--omega", omega] if omega else []))
    scene = bk.load_scene(scene_file, omega=None if omega is None else 320 * math.pi)
    cli.pop("chaos_check")  # (the CLI's verdict on the table: bk.chaos)
    assert bk.coefficients(scene) == cli
    # The same from the shape and the drive.
    F = scene.force["amplitude"]
    direct = bk.coefficients(scene.shape, F=F, omega=scene.force["omega"], E=scene.energy)
    assert direct == cli


def test_coefficients_need_a_drive(source):
    with pytest.raises(bk.InputError, match="periodic force"):
        bk.coefficients(bk.load_scene(source / "scenes" / "clover-free.yaml"))


def test_fokker_planck_numerical_against_analytic_and_cli(source, tmp_path):
    s = np.array([0.1, 1.0, 10.0])
    E, eta, edges = bk.fokker_planck_numerical(s, 0.5, cells=4000)
    assert eta.shape == (3, 4000) and E.shape == (4000,) and edges.shape == (4001,)
    assert np.allclose(E, (edges[1:] + edges[:-1]) / 2, rtol=1e-15)
    dE = np.diff(edges)
    for k, sk in enumerate(s):
        exact = bk.fokker_planck_eta(E, sk, 0.5)
        assert np.sum(np.abs(eta[k] - exact) * dE) < 2e-3   # L1 distance
        m = bk.fokker_planck_moments(sk, 0.5)
        assert np.sum(E * exact * dE) == pytest.approx(m["mean"], rel=1e-3)
    # The scheme conserves the mass it starts from (the short-time law, normalized on the cells).
    mass = eta @ dE
    assert np.ptp(mass) < 1e-12 and mass[0] == pytest.approx(1, abs=1e-4)
    # `billiard fp` gives the same columns (C t = s for the scene's C).
    scene = bk.load_scene(source / "scenes" / "clover-driven.yaml")
    C = bk.coefficients(scene)["C"]
    out = tmp_path / "fp.csv"
    billiard("fp", source / "scenes" / "clover-driven.yaml", "--times", "10,100", "--cells", 500, "-o", out)
    table = np.loadtxt(out, delimiter=",", skiprows=1)
    E, eta, _ = bk.fokker_planck_numerical([C * 10, C * 100], scene.energy, cells=500)
    assert np.allclose(table[:, 0], E, rtol=1e-9)
    assert np.allclose(table[:, 1], eta[0], rtol=1e-8, atol=1e-12)
    assert np.allclose(table[:, 3], eta[1], rtol=1e-8, atol=1e-12)
    assert np.allclose(table[:, 2], bk.fokker_planck_eta(E, C * 10, scene.energy), rtol=1e-8, atol=1e-12)


# --- runs ----------------------------------------------------------------------------------

def clover_scene_dict():
    """scenes/clover-driven.yaml as a dict (the shape path is relative to scenes/)."""
    return {"shape": "../shapes/clover.yaml", "parameters": {"F": 10, "omega": "40*pi"}, "mass": 1,
            "initial": {"microcanonical": {"energy": "1/2"}},
            "force": {"periodic": {"amplitude": ["F/sqrt(2)", "F/sqrt(2)"], "omega": "omega", "phase": 0}},
            "run": {"particles": 20000, "time": 20, "record": {"every": 1}, "seed": 1}}


@pytest.mark.parametrize("scene_name", ["clover-driven", "clover-free", "sinai3-driven"])
def test_run_equals_cli_energies_byte_for_byte(source, tmp_path, scene_name):
    scene_file = source / "scenes" / f"{scene_name}.yaml"
    out = tmp_path / "run"
    billiard("run", scene_file, "--particles", 300, "--time", 6, "--seed", 7, "--out", out, "--no-csv", "--quiet",
             "--threads", 1)
    cli = np.load(out / "energies.npy")
    summary = json.loads((out / "summary.json").read_text())
    result = bk.run(bk.load_scene(scene_file, particles=300, time=6, seed=7), threads=2)
    energies = result["energies"]
    assert energies.shape == cli.shape and energies.dtype == cli.dtype
    assert energies.tobytes() == cli.tobytes()
    assert np.array_equal(result["record_times"], summary["record_times"])
    assert int(result["collisions"].sum()) == summary["collisions"]
    assert not result["escaped"].any()


def test_scene_from_dict_equals_scene_file(source):
    from_file = bk.run(bk.load_scene(source / "scenes" / "clover-driven.yaml", particles=64, time=3))
    from_dict = bk.run(bk.load_scene(clover_scene_dict(), particles=64, time=3,
                                                   base_dir=source / "scenes"))
    assert from_dict["energies"].tobytes() == from_file["energies"].tobytes()


def test_thread_count_does_not_change_the_numbers(source):
    scene = bk.load_scene(source / "scenes" / "clover-driven.yaml", particles=203, time=8)
    runs = [bk.run(scene, threads=k) for k in (1, 2, 3)]
    for r in runs[1:]:
        assert r["energies"].tobytes() == runs[0]["energies"].tobytes()
        assert np.array_equal(r["collisions"], runs[0]["collisions"])


def test_arrays_own_the_cpp_buffers(source):
    result = bk.run(bk.load_scene(source / "scenes" / "clover-free.yaml", particles=10, time=30))
    for key in ("energies", "collisions", "escaped"):
        a = result[key]
        assert not a.flags.owndata and a.base is not None, key  # a capsule holds the C++ vector
    # collisions and escaped are views into the same per-particle records.
    assert result["collisions"].strides == result["escaped"].strides == (16,)
    assert result["collisions"].dtype == np.uint64 and result["escaped"].dtype == np.bool_
    assert (result["collisions"] > 0).all()


def test_run_releases_the_gil(source):
    """A second Python thread ticks during the middle of a run only if the run released the GIL."""
    scene = bk.load_scene(source / "scenes" / "clover-driven.yaml", particles=2000, time=600)
    ticks, stop = [], threading.Event()

    def tick():
        while not stop.is_set():
            ticks.append(time.perf_counter())
            time.sleep(0.001)

    ticker = threading.Thread(target=tick)
    ticker.start()
    time.sleep(0.02)
    t0 = time.perf_counter()
    bk.run(scene, threads=1)
    t1 = time.perf_counter()
    stop.set()
    ticker.join()
    assert t1 - t0 > 0.05, "the run is too short to tell"
    middle = [t for t in ticks if t0 + 0.25 * (t1 - t0) < t < t1 - 0.25 * (t1 - t0)]
    assert len(middle) >= 5, f"{len(middle)} ticks in the middle half of a {t1 - t0:.2f} s run"


# --- trajectories --------------------------------------------------------------------------

def distance_to_boundary(p, pieces):
    """Distance from p to the nearest piece (segments, and arcs by their full circles)."""
    best = math.inf
    for q in pieces:
        if q["kind"] == "arc":
            d = abs(math.dist(p, q["center"]) - q["radius"])
        else:
            a, b = np.array(q["from"]), np.array(q["to"])
            u = np.clip(np.dot(p - a, b - a) / np.dot(b - a, b - a), 0, 1)
            d = np.linalg.norm(p - (a + u * (b - a)))
        best = min(best, d)
    return best


@pytest.mark.parametrize("scene_name", ["clover-driven", "clover-free"])
def test_trajectory_points_lie_on_the_boundary(source, scene_name):
    scene = bk.load_scene(source / "scenes" / f"{scene_name}.yaml")
    traj = bk.trajectory(scene, collisions=200, particle=5)
    x, v, t = traj["positions"], traj["velocities"], traj["times"]
    assert x.shape == (201, 2) and v.shape == (201, 2) and not traj["escaped"]
    assert (np.diff(t) >= 0).all() and traj["walls"][0] == -1 and (traj["walls"][1:] >= 0).all()
    pieces = scene.shape.info()["pieces"]
    assert max(distance_to_boundary(p, pieces) for p in x[1:]) < 1e-12
    assert distance_to_boundary(x[0], pieces) > 1e-6  # the start is inside, not on a wall
    speed = np.hypot(v[:, 0], v[:, 1])
    if scene_name == "clover-free":
        assert np.allclose(speed, 1, rtol=1e-14)
    else:
        assert not np.allclose(speed, 1, rtol=1e-3)  # the drive changes the speed at each bounce


def test_trajectory_in_3d_hits_the_walls(source):
    """The 3-D Sinai billiard: the unit cube [-1/2, 1/2]^3 minus a ball of radius 1/4 at its centre."""
    scene = bk.load_scene(source / "scenes" / "sinai3-driven.yaml")
    traj = bk.trajectory(scene, collisions=100, particle=2)
    x = traj["positions"][1:]
    assert x.shape == (100, 3) and not traj["escaped"]
    on_cube = np.abs(np.max(np.abs(x), axis=1) - 0.5) < 1e-12   # L = 1
    on_ball = np.abs(np.linalg.norm(x, axis=1) - 0.25) < 1e-12  # R = 1/4
    assert (on_cube | on_ball).all() and on_cube.any() and on_ball.any()


def test_trajectory_is_the_runs_particle(source):
    """The collisions of particle i before the end time are those `run` counts for it."""
    scene = bk.load_scene(source / "scenes" / "clover-driven.yaml", particles=20, time=20)
    counts = bk.run(scene)["collisions"]
    for i in (0, 7, 19):
        times = bk.trajectory(scene, collisions=int(counts[i]) + 10, particle=i)["times"]
        assert np.count_nonzero(times[1:] <= scene.time) == counts[i]


@pytest.mark.parametrize("shape", ["clover", "sinai", "mushroom"])
def test_outline_lies_on_the_boundary_and_encloses_the_area(source, shape):
    shape = bk.load_shape(source / "shapes" / f"{shape}.yaml")
    info = shape.info()
    loops = shape.outline()
    assert len(loops) == 1 + info["holes"]
    for xy in loops:
        assert max(distance_to_boundary(p, info["pieces"]) for p in xy) < 1e-12
    # Shoelace: the outer loop counter-clockwise, holes clockwise; chords of half a degree
    # cut off a relative area of about (pi/360)^2/12 = 6e-6 of each arc's sector.
    area = sum(0.5 * np.sum(xy[:, 0] * np.roll(xy[:, 1], -1) - np.roll(xy[:, 0], -1) * xy[:, 1]) for xy in loops)
    assert area == pytest.approx(info["V"], rel=1e-4)


def test_free_trajectory_in_a_square_reflects_specularly():
    square = bk.load_shape({"boundary": {"polygon": [[0, 0], [1, 0], [1, 1], [0, 1]]}})
    traj = bk.trajectory(square, collisions=50, seed=3)
    v = traj["velocities"]
    # Reflections off axis-parallel walls keep |vx| and |vy|.
    assert np.allclose(np.abs(v), np.abs(v[0]), rtol=1e-14)
    x = traj["positions"][1:, 0]
    walls_x = np.minimum(np.abs(x), np.abs(x - 1)) < 1e-12  # hits on x = 0 or x = 1
    flipped_x = np.sign(v[1:, 0]) != np.sign(v[:-1, 0])
    assert np.array_equal(walls_x, flipped_x)


def test_example_script_writes_a_png(source, tmp_path):
    out = tmp_path / "fig2.png"
    done = subprocess.run([sys.executable, str(source / "examples" / "paper_fig2.py"), "--particles", "200",
                           "--times", "1,5", "--output", str(out)], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


@pytest.mark.parametrize("shape_file", ["shapes/clover.yaml", "shapes/3d/sinai3.yaml", "shapes/3d/l-prism.yaml"])
def test_plot_draws_the_modules_trajectory(source, tmp_path, shape_file):
    """`billiard plot --trajectory K --seed S` draws the points of bk.trajectory(shape,
    seed=S): a stand-in drawing script (BILLIARDS_SCRIPTS) saves the data it is handed."""
    for name in ("plot_shape.py", "plot_shape3.py"):
        (tmp_path / name).write_text("import shutil, sys\nshutil.copy(sys.argv[1], sys.argv[1] + '.kept')\n"
                                     "shutil.copy(sys.argv[1], sys.argv[2])\n")
    env = dict(os.environ, BILLIARDS_SCRIPTS=str(tmp_path), TMPDIR=str(tmp_path))
    done = subprocess.run([BINARY, "plot", str(source / shape_file), "-o", str(tmp_path / "out.png"),
                           "--trajectory", "40", "--seed", "7"], capture_output=True, text=True, env=env)
    assert done.returncode == 0, done.stderr
    (kept,) = tmp_path.glob("billiard-plot-*.json.kept")
    drawn = np.array(json.loads(kept.read_text())["trajectory"])
    walk = bk.trajectory(bk.load_shape(source / shape_file), collisions=40, seed=7)
    assert not walk["escaped"]
    np.testing.assert_array_equal(drawn, walk["positions"])


def test_phase_space_functions_give_the_programs_numbers(source, tmp_path):
    """bk.boundary_map is bmap.npy, bk.lyapunov and bk.chaos are the --json figures of the CLI."""
    shape = bk.load_shape(source / "shapes" / "clover.yaml")
    rows = bk.boundary_map(shape, particles=3, collisions=200, seed=4)
    billiard("bmap", "shapes/clover.yaml", "--particles", 3, "--collisions", 200, "--seed", 4, "--quiet",
             "--no-csv", "--out", tmp_path / "bmap")
    assert rows.shape == (600, 6)
    assert np.array_equal(rows, np.load(tmp_path / "bmap" / "bmap.npy"))
    lyap = bk.lyapunov(shape, particles=3, collisions=2000)
    cli = billiard_json("lyapunov", "shapes/clover.yaml", "--particles", 3, "--collisions", 2000, "--quiet")
    assert lyap["lyapunov"] == cli["lyapunov"] and lyap["lyapunov_se"] == cli["lyapunov_se"]
    assert np.allclose(lyap["per_trajectory"].sum(axis=1), 0, atol=1e-9)
    # (50 000 collisions an orbit, as the CLI's default: its distance to uniform, ~0.03, stays clear of 0.1)
    assert bk.chaos(shape, orbits=3, collisions=50000)["ergodic"] is True
    rows = bk.boundary_map(shape, particles=3, collisions=200, seed=4, section="y = 0.2")
    billiard("bmap", "shapes/clover.yaml", "--section", "y = 0.2", "--particles", 3, "--collisions", 200, "--seed", 4,
             "--quiet", "--no-csv", "--out", tmp_path / "line")
    assert rows.shape[1] == 6 and np.array_equal(rows, np.load(tmp_path / "line" / "section.npy"))
    forced = source / "scenes" / "clover-magnetic-driven.yaml"
    with pytest.raises(ValueError, match="needs a time horizon"):  # (a magnetic field with a force)
        bk.boundary_map(bk.load_scene(forced))
    # bk.lyapunov follows such a scene to successive horizons, as the CLI does.
    lyap = bk.lyapunov(bk.load_scene(forced), particles=3, collisions=1000)
    cli = billiard_json("lyapunov", forced, "--particles", 3, "--collisions", 1000, "--quiet")
    assert list(lyap["spectrum"]) == cli["spectrum"] and lyap["trapped"] == cli["trapped"] == 0
    assert lyap["spectrum"][0] > 0
    with pytest.raises(ValueError, match="give time="):
        bk.trajectory(bk.load_scene(source / "scenes" / "clover-magnetic-driven.yaml"), collisions=50)
    assert bk.trajectory(bk.load_scene(source / "scenes" / "clover-magnetic-driven.yaml"), time=2)["times"][-1] <= 2


def test_escape_gives_the_programs_numbers_and_kacs_lemma(source, tmp_path):
    """bk.escape: the arrays of escape.csv, the --json summary, and Kac's mean pi V / (w v)."""
    shape_path = tmp_path / "clover-open.yaml"
    shape_path.write_text((source / "shapes" / "clover.yaml").read_text() +
                          "exits:\n  - {from: [R1*sin(0.1), a + R1*cos(0.1)], to: [-R1*sin(0.1), a + R1*cos(0.1)]}\n")
    shape = bk.load_shape(shape_path)
    r = bk.escape(shape, particles=4000, seed=3, entering=True)
    cli = billiard_json("escape", shape_path, "--particles", 4000, "--seed", 3, "--entering", "--quiet",
                        "--out", tmp_path / "escape")
    assert r["mean_escape_time"] == cli["mean_escape_time"]
    assert r["mean_escape_time_se"] == cli["mean_escape_time_se"]
    assert r["exit_length"] == pytest.approx(0.2, rel=1e-12)
    table = np.loadtxt(tmp_path / "escape" / "escape.csv", delimiter=",", skiprows=1)
    assert np.array_equal(r["escape_times"], table[:, 1]) and np.array_equal(r["collisions"], table[:, 2])
    assert r["escaped"].all() and r["escape_times"].mean() == pytest.approx(r["mean_escape_time"], rel=1e-12)
    assert abs(r["mean_escape_time"] - np.pi * bk.info(shape)["V"] / 0.2) < 3 * r["mean_escape_time_se"]
    # P(t): 1 at t = 0, 0 after the last escape, and the fraction still inside in between.
    t, P = r["survival_t"], r["survival_P"]
    assert P[0] == 1 and P[-1] == 0
    k = len(t) // 3
    assert P[k] == pytest.approx((r["escape_times"] > t[k]).mean(), abs=1e-12)
