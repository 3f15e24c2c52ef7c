"""3-D shapes in the Python module: against `billiard info/coeffs/run`, against closed forms and
independent sums over the drawn geometry, and trajectories that stay on the walls."""
import gc
import json
import math

import numpy as np
import pytest

import billiardkit as bk
from conftest import billiard, billiard_json

SHAPES3 = ["cube", "ball", "sinai3", "octahedron", "l-prism"]


def shape3_path(source, name):
    return source / "shapes" / "3d" / f"{name}.yaml"


# --- shapes --------------------------------------------------------------------------------

@pytest.mark.parametrize("name,set_", [("cube", {}), ("ball", {}), ("sinai3", {}), ("sinai3", {"L": "2", "R": "0.3"}),
                                       ("octahedron", {}), ("l-prism", {})])
def test_info_equals_cli(source, name, set_):
    path = shape3_path(source, name)
    sets = [a for k, v in set_.items() for a in ("--set", f"{k}={v}")]
    cli = billiard_json("info", path, *sets)
    shape = bk.load_shape(path, set=set_)
    assert isinstance(shape, bk.Shape3) and shape.dimension == 3
    py = shape.info()
    assert set(py) == set(cli) | {"description"}
    for key, value in cli.items():
        if key in ("boundary_tensor", "bbox"):
            assert py[key].dtype == np.float64 and np.array_equal(py[key], np.array(value)), key
        else:
            assert py[key] == value, key
    assert py["boundary_tensor"].shape == (3, 3) and py["bbox"].shape == (2, 3)
    assert bk.info(path, set=set_)["V"] == cli["V"]  # from the path directly


def test_dimension_picks_the_type(source):
    flat = bk.load_shape(source / "shapes" / "clover.yaml")
    assert isinstance(flat, bk.Shape) and flat.dimension == 2
    solid = bk.load_shape({"dimension": 3, "boundary": {"sphere": {"center": [0, 0, 0], "radius": 2}}})
    assert isinstance(solid, bk.Shape3) and solid.name == "shape dict"
    assert solid.info()["V"] == pytest.approx(32 * math.pi / 3, rel=1e-15)
    assert repr(solid) == "<billiardkit.Shape3 'shape dict'>"


def drawn_measures(shape):
    """V, S and the integral of n n^T dS from Shape3.mesh() and Shape3.spheres() alone: the
    divergence theorem and the triangles' cross products, and the closed forms of spheres."""
    vertices, triangles = shape.mesh()
    a, b, c = (vertices[triangles[:, k]] for k in range(3))
    cross = np.cross(b - a, c - a)                      # 2 area n, n outward
    area = np.linalg.norm(cross, axis=1) / 2
    assert (area > 0).all()
    n = cross / (2 * area[:, None])
    V = np.einsum("ij,ij->i", a, cross).sum() / 6       # sum of signed tetrahedra from the origin
    S = area.sum()
    T = np.einsum("i,ij,ik->jk", area, n, n)
    for sphere in shape.spheres():
        r = sphere["radius"]
        V += (1 if sphere["outer"] else -1) * 4 * math.pi * r ** 3 / 3
        S += 4 * math.pi * r ** 2
        T += 4 * math.pi * r ** 2 / 3 * np.eye(3)
    return V, S, T


@pytest.mark.parametrize("name", SHAPES3)
def test_drawn_geometry_has_the_shapes_measures(source, name):
    shape = bk.load_shape(shape3_path(source, name))
    info = shape.info()
    V, S, T = drawn_measures(shape)
    assert V == pytest.approx(info["V"], rel=1e-13)
    assert S == pytest.approx(info["S"], rel=1e-13)
    assert np.allclose(T, info["boundary_tensor"], rtol=0, atol=1e-13 * info["S"])
    vertices, triangles = shape.mesh()
    assert vertices.shape[1] == 3 and triangles.shape[1] == 3 and triangles.dtype == np.int32
    if info["boundary"]["kind"] == "mesh":
        assert len(vertices) == info["boundary"]["vertices"] and len(triangles) == info["boundary"]["triangles"]
    lo, hi = info["bbox"]
    if len(vertices):
        assert np.array_equal(vertices.min(axis=0), lo) and np.array_equal(vertices.max(axis=0), hi)


def test_spheres_are_those_of_the_file(source):
    (ball,) = bk.load_shape(shape3_path(source, "ball")).spheres()
    assert ball["outer"] and ball["radius"] == 1 and np.array_equal(ball["center"], [0, 0, 0])
    assert bk.load_shape(shape3_path(source, "ball")).mesh()[0].shape == (0, 3)
    sinai3 = bk.load_shape(shape3_path(source, "sinai3"), set={"R": 0.3})
    (hole,) = sinai3.spheres()
    assert not hole["outer"] and hole["radius"] == 0.3
    assert len(bk.load_shape(shape3_path(source, "cube")).spheres()) == 0


def test_mesh_dict_is_read_relative_to_base_dir(source):
    shape = bk.load_shape({"dimension": 3, "boundary": {"mesh": "l-prism.off"}},
                                 base_dir=source / "shapes" / "3d")
    assert shape.info()["V"] == pytest.approx(6, rel=1e-14)  # the file's comment: V = 6, S = 22
    with pytest.raises(bk.InputError, match=r"shape dict:\d+: .*l-prism\.off"):
        bk.load_shape({"dimension": 3, "boundary": {"mesh": "l-prism.off"}}, base_dir=source)


def line_of(d, text):
    """The line of the dumped dict (one key per line, as the module writes it) holding `text`."""
    lines = json.dumps(d, indent=1).splitlines()
    return next(i + 1 for i, line in enumerate(lines) if text in line)


def test_malformed_3d_dicts_raise_with_file_line_and_reason():
    bad_box = {"dimension": 3, "boundary": {"box": {"min": [0, 0, 0], "max": [1, 1]}}}
    with pytest.raises(bk.InputError, match=rf"^shape dict:{line_of(bad_box, 'max')}: expected a vector \[x, y, z\]"):
        bk.load_shape(bad_box)
    ball_outside = {"dimension": 3, "boundary": {"box": {"min": [0, 0, 0], "max": [1, 1, 1]}},
                    "holes": [{"ball": {"center": [0.9, 0.5, 0.5], "radius": 0.2}}]}
    with pytest.raises(bk.InputError, match=r"^shape dict:\d+: this ball crosses or touches the plane"):
        bk.load_shape(ball_outside)
    four = {"dimension": 4, "boundary": {"sphere": {"center": [0, 0, 0], "radius": 1}}}
    with pytest.raises(bk.InputError, match=rf"^shape dict:{line_of(four, 'dimension')}: 'dimension' must be 2 or 3"):
        bk.load_shape(four)
    with pytest.raises(bk.InputError, match=r"^shape dict:\d+: .*radius"):
        bk.load_shape({"dimension": 3, "boundary": {"sphere": {"center": [0, 0, 0], "radius": -1}}})
    with pytest.raises(bk.InputError, match="octopus"):
        bk.load_shape({"dimension": 3, "boundary": {"octopus": 1}})


# --- scenes --------------------------------------------------------------------------------

def test_scene_shape_in_3d(source):
    scene = bk.load_scene(source / "scenes" / "sinai3-driven.yaml")
    shape = scene.shape
    assert isinstance(shape, bk.Shape3) and shape.name == "sinai3"
    expected = bk.load_shape(shape3_path(source, "sinai3")).info()
    del scene
    gc.collect()  # the shape is a view that keeps the scene alive
    info = shape.info()
    assert info["V"] == expected["V"] and np.array_equal(info["boundary_tensor"], expected["boundary_tensor"])


def test_coefficients_in_3d_equal_cli(source):
    scene_file = source / "scenes" / "sinai3-driven.yaml"
    cli = billiard_json("coeffs", scene_file)
    scene = bk.load_scene(scene_file)
    assert cli.pop("chaos_check") is None  # (2-D only)
    assert cli["dimension"] == 3 and bk.coefficients(scene) == cli
    F = scene.force["amplitude"]
    assert bk.coefficients(scene.shape, F=F, omega=scene.force["omega"], E=scene.energy) == cli
    with pytest.raises(ValueError, match="F must have 3 components"):
        bk.coefficients(scene.shape, F=[1, 0], omega=1, E=1)


def free_l_prism_scene(source):
    return {"shape": str(shape3_path(source, "l-prism")), "initial": {"microcanonical": {"energy": 2}}, "run": {"particles": 200, "time": 5, "record": {"every": 1}, "seed": 3}}


def test_free_3d_run_equals_cli(source, tmp_path):
    """A free run in a mesh (the driven 3-D Sinai is in test_billiards.py)."""
    scene_file = tmp_path / "free3.yaml"
    scene_file.write_text(json.dumps(free_l_prism_scene(source), indent=1))
    out = tmp_path / "run"
    billiard("run", scene_file, "--out", out, "--no-csv", "--quiet", "--threads", 1)
    cli = np.load(out / "energies.npy")
    summary = json.loads((out / "summary.json").read_text())
    result = bk.run(bk.load_scene(scene_file), threads=2)
    assert result["energies"].tobytes() == cli.tobytes()
    assert int(result["collisions"].sum()) == summary["collisions"] > 0
    assert not result["escaped"].any()


# --- trajectories --------------------------------------------------------------------------

def distance_to_triangles(p, vertices, triangles):
    """Distance from p to the nearest triangle: to its plane if p projects inside it, else to its
    nearest edge."""
    a, b, c = (vertices[triangles[:, k]] for k in range(3))
    n = np.cross(b - a, c - a)
    n /= np.linalg.norm(n, axis=1)[:, None]
    height = np.einsum("ij,ij->i", p - a, n)
    q = p - height[:, None] * n
    inside = np.ones(len(a), dtype=bool)
    edges = np.full(len(a), np.inf)
    for u, v in ((a, b), (b, c), (c, a)):
        inside &= np.einsum("ij,ij->i", np.cross(v - u, q - u), n) >= 0
        s = np.clip(np.einsum("ij,ij->i", p - u, v - u) / np.einsum("ij,ij->i", v - u, v - u), 0, 1)
        edges = np.minimum(edges, np.linalg.norm(p - (u + s[:, None] * (v - u)), axis=1))
    return np.min(np.where(inside, np.abs(height), edges)) if len(a) else np.inf


def distance_to_walls(p, shape):
    vertices, triangles = shape.mesh()
    spheres = [abs(np.linalg.norm(p - s["center"]) - s["radius"]) for s in shape.spheres()]
    return min([distance_to_triangles(p, vertices, triangles), *spheres])


def check_on_the_walls(traj, shape, collisions):
    x, v, t = traj["positions"], traj["velocities"], traj["times"]
    assert x.shape == v.shape == (collisions + 1, 3) and not traj["escaped"]
    assert (np.diff(t) > 0).all() and traj["walls"][0] == -1 and (traj["walls"][1:] >= 0).all()
    assert max(distance_to_walls(p, shape) for p in x[1:]) < 1e-12
    assert distance_to_walls(x[0], shape) > 1e-6  # the start is inside, not on a wall
    # Straight flights in between: each displacement is the velocity before it times the time.
    assert np.allclose(np.diff(x, axis=0), v[:-1] * np.diff(t)[:, None], rtol=0, atol=1e-12)
    return np.linalg.norm(v, axis=1)


def test_free_trajectory_in_a_3d_scene_stays_on_the_walls_at_constant_speed(source):
    scene = bk.load_scene(free_l_prism_scene(source))
    traj = bk.trajectory(scene, collisions=300, particle=4)
    speed = check_on_the_walls(traj, scene.shape, 300)
    assert np.allclose(speed, 2, rtol=1e-14)  # E = 2, m = 1


@pytest.mark.parametrize("name", ["octahedron", "ball", "sinai3"])
def test_free_trajectory_in_a_shape3(source, name):
    shape = bk.load_shape(shape3_path(source, name))
    traj = bk.trajectory(shape, collisions=200, seed=5, speed=3)
    speed = check_on_the_walls(traj, shape, 200)
    assert np.allclose(speed, 3, rtol=1e-14)
    again = bk.trajectory(shape, collisions=200, seed=5, speed=3)
    assert again["positions"].tobytes() == traj["positions"].tobytes()
    other = bk.trajectory(shape, collisions=200, seed=5, particle=1, speed=3)
    assert not np.array_equal(other["positions"][0], traj["positions"][0])


# --- phase space ---------------------------------------------------------------------------

def test_phase_space_functions_in_3d_give_the_programs_numbers(source, tmp_path):
    """bk.lyapunov, bk.chaos and bk.escape take a Shape3 or a 3-D Scene as `billiard lyapunov`,
    `chaos` and `escape` take the files; bk.boundary_map refuses them as `bmap` without --section."""
    path = shape3_path(source, "sinai3")
    shape = bk.load_shape(path)
    lyap = bk.lyapunov(shape, particles=3, collisions=2000)
    cli = billiard_json("lyapunov", path, "--particles", 3, "--collisions", 2000, "--quiet")
    assert lyap["dimension"] == 3 and lyap["per_trajectory"].shape == (3, 6)
    assert list(lyap["spectrum"]) == cli["spectrum"] and lyap["lyapunov_se"] == cli["lyapunov_se"]
    assert np.allclose(lyap["per_trajectory"].sum(axis=1), 0, atol=1e-9)  # (the volume is kept)
    magnetic = source / "scenes" / "sinai3-magnetic.yaml"
    lyap = bk.lyapunov(bk.load_scene(magnetic), particles=3, collisions=1000)
    cli = billiard_json("lyapunov", magnetic, "--particles", 3, "--collisions", 1000, "--quiet")
    assert list(lyap["spectrum"]) == cli["spectrum"] and lyap["trapped"] == cli["trapped"] == 0
    cube = shape3_path(source, "cube")
    verdict = bk.chaos(bk.load_shape(cube), orbits=3, collisions=4000)
    cli = billiard_json("chaos", cube, "--particles", 3, "--collisions", 4000, "--quiet")
    assert verdict["ergodic"] is False and cli["ergodic"] is False
    assert verdict["lyapunov"] == cli["lyapunov"] and verdict["pooled_distance"] == cli["pooled_distance"]
    open_path = tmp_path / "sinai3-open.yaml"
    open_path.write_text(path.read_text() + "exits:\n  - disc: {center: [L/2, 0.1, -0.1], radius: 0.2}\n")
    r = bk.escape(bk.load_shape(open_path), particles=300, seed=3, entering=True)
    cli = billiard_json("escape", open_path, "--particles", 300, "--seed", 3, "--entering", "--quiet",
                        "--out", tmp_path / "escape")
    assert r["dimension"] == 3 and r["exit_length"] == pytest.approx(math.pi * 0.04, rel=1e-12)
    assert r["mean_escape_time"] == cli["mean_escape_time"] and r["kac_mean_escape_time"] == cli["kac_mean_escape_time"]
    table = np.loadtxt(tmp_path / "escape" / "escape.csv", delimiter=",", skiprows=1)
    assert np.array_equal(r["escape_times"], table[:, 1]) and np.array_equal(r["collisions"], table[:, 2])
    with pytest.raises(ValueError, match="3-D table has no boundary map"):
        bk.boundary_map(shape)


def test_boundary_map_gives_the_programs_plane_sections(source, tmp_path):
    """bk.boundary_map(section=...) of a Shape3 or a 3-D Scene is `billiard bmap --section`'s
    section3.npy, row for row; a bad plane is an InputError, as on the command line."""
    path = shape3_path(source, "sinai3")
    rows = bk.boundary_map(bk.load_shape(path), particles=3, collisions=300, seed=4, section="x + 2*z = 0.3")
    billiard("bmap", path, "--section", "x + 2*z = 0.3", "--particles", 3, "--collisions", 300, "--seed", 4,
             "--quiet", "--no-csv", "--out", tmp_path / "plane")
    assert rows.shape[1] == 8 and rows.shape[0] > 100
    assert np.array_equal(rows, np.load(tmp_path / "plane" / "section3.npy"))
    assert np.all(np.abs(rows[:, 4:6]) <= 1)  # (p1, p2: components of the unit velocity)
    driven = source / "scenes" / "sinai3-driven.yaml"
    rows = bk.boundary_map(bk.load_scene(driven), particles=2, collisions=200, section="z = 0")
    billiard("bmap", driven, "--section", "z = 0", "--particles", 2, "--collisions", 200, "--quiet", "--no-csv",
             "--out", tmp_path / "driven")
    assert np.array_equal(rows, np.load(tmp_path / "driven" / "section3.npy"))
    with pytest.raises(bk.InputError, match="not linear in x, y and z"):
        bk.boundary_map(bk.load_shape(path), section="x*z = 0")
    with pytest.raises(ValueError, match="a section is drawn for free flights"):
        bk.boundary_map(bk.load_scene(source / "scenes" / "sinai3-magnetic.yaml"), section="z = 0")
