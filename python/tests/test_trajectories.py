"""Dense and streamed trajectories, Ctrl-C in long ones, and animations (billiardkit.animate and
`billiard animate`): checked against closed forms, against each other, and by decoding the movie."""
import json
import pathlib
import shutil
import subprocess
import sys
import threading

import numpy as np
import pytest

import billiardkit as bk
from billiardkit import movie
from conftest import BINARY, interrupted


def scene(source, name="clover-driven", **kw):
    return bk.Scene(source / "scenes" / f"{name}.yaml", **kw)


def test_dense_samples_follow_the_driven_closed_form(source):
    """Between bounces, x(t) = x_s + (v_s - (F/m w) sin th_s)(t - t_s) - (F/m w^2)(cos th - cos th_s)."""
    sc = scene(source, particles=4)
    f = sc.force
    a, w, phase = np.array(f["amplitude"]) / sc.mass, f["omega"], f["phase"]
    traj = bk.trajectory(sc, collisions=40, particle=3, dt=1e-3)
    s = traj["samples"]
    k = np.searchsorted(traj["times"], s["times"], side="right") - 1  # the flight each sample is on
    ts, xs, vs = traj["times"][k], traj["positions"][k], traj["velocities"][k]
    th_s, th = w * ts + phase, w * s["times"] + phase
    x = xs + (vs - np.outer(np.sin(th_s), a / w)) * (s["times"] - ts)[:, None] \
        - np.outer(np.cos(th) - np.cos(th_s), a / w**2)
    assert np.abs(s["positions"] - x).max() < 1e-11
    assert np.array_equal(s["times"], np.arange(len(s["times"])) * 1e-3)
    assert s["times"][-1] <= traj["times"][-1] < s["times"][-1] + 1e-3
    assert np.allclose(s["energies"], 0.5 * sc.mass * (s["velocities"] ** 2).sum(axis=1), rtol=1e-15)


def test_streamed_trajectory_equals_the_collected_one(source):
    sc = scene(source, particles=2)
    whole = bk.trajectory(sc, collisions=5000, dt=0.01)
    chunks = []
    summary = bk.trajectory(sc, collisions=5000, dt=0.01, on_chunk=chunks.append, chunk=1000)
    assert summary == {"collisions": 5000, "escaped": False, "trapped": False}
    assert len(chunks) > 5 and all(len(c["times"]) <= 1000 and len(c["samples"]["times"]) <= 1000 for c in chunks)
    for key in ("times", "positions", "velocities", "walls"):
        assert np.concatenate([c[key] for c in chunks]).tobytes() == whole[key].tobytes(), key
    for key in ("times", "positions", "velocities", "energies"):
        assert np.concatenate([c["samples"][key] for c in chunks]).tobytes() == whole["samples"][key].tobytes(), key


def test_trajectory_stops_at_its_time(source):
    sc = scene(source, particles=2)
    traj = bk.trajectory(sc, time=1.5, dt=0.25)
    assert traj["times"][-1] <= 1.5 and np.array_equal(traj["samples"]["times"], np.arange(7) * 0.25)
    shape = bk.load_shape(source / "shapes" / "clover.yaml")
    free = bk.trajectory(shape, time=3.0, dt=0.5)
    assert np.array_equal(free["samples"]["times"], np.arange(7) * 0.5)
    assert np.allclose(np.hypot(*free["samples"]["velocities"].T), 1, rtol=1e-14)


# 2e6 collisions streamed by callback or by iterator; each script sets `collisions` and `rows`.
STREAMS = {
    "on_chunk": ("n = [0]\n"
                 "def count(c): n[0] += len(c['times'])\n"
                 "r = bk.trajectory(shape, collisions=2_000_000, on_chunk=count, chunk=10000)\n"
                 "collisions, rows = r['collisions'], n[0]\n"),
    "iterator": ("chunks = bk.trajectory_chunks(shape, collisions=2_000_000, chunk=10000, progress=False)\n"
                 "rows = sum(len(c['times']) for c in chunks)\n"
                 "collisions = chunks.collisions\n"),
}


@pytest.mark.parametrize("stream", sorted(STREAMS))
def test_a_long_stream_runs_in_bounded_memory(source, stream):
    """2e6 collisions streamed: the process's peak memory grows by far less than the ~110 MB the
    collected rows would take (7 doubles a bounce)."""
    script = ("import billiardkit as bk, resource\n"
              f"shape = bk.load_shape({str(source / 'shapes' / 'circle.yaml')!r})\n"
              "bk.trajectory(shape, collisions=1000, on_chunk=lambda c: None)\n"
              "list(bk.trajectory_chunks(shape, collisions=1000))\n"
              "before = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss\n"
              + STREAMS[stream] +
              "print(collisions, rows, resource.getrusage(resource.RUSAGE_SELF).ru_maxrss - before)\n")
    out = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, check=True).stdout.split()
    collisions, rows, growth_kb = map(int, out)
    assert collisions == 2_000_000 and rows == 2_000_001
    assert growth_kb < 10_000


def test_iterated_chunks_equal_the_collected_trajectory(source):
    sc = scene(source, particles=4)
    whole = bk.trajectory(sc, collisions=3000, dt=0.01, particle=2)
    with bk.trajectory_chunks(sc, collisions=3000, dt=0.01, particle=2, chunk=700) as chunks:
        got = list(chunks)
    assert (chunks.collisions, chunks.escaped, chunks.trapped) == (3000, False, False)
    assert len(got) > 4 and all(len(c["times"]) <= 700 and len(c["samples"]["times"]) <= 700 for c in got)
    for key in ("times", "positions", "velocities", "walls"):
        assert np.concatenate([c[key] for c in got]).tobytes() == whole[key].tobytes(), key
    for key in ("times", "positions", "velocities", "energies"):
        assert np.concatenate([c["samples"][key] for c in got]).tobytes() == whole["samples"][key].tobytes(), key
    shape = bk.load_shape(source / "shapes" / "3d" / "sinai3.yaml")
    free = bk.trajectory(shape, collisions=500, seed=4)
    got = list(bk.trajectory_chunks(shape, collisions=500, seed=4, chunk=64))
    assert got[0]["samples"] is None
    assert np.concatenate([c["positions"] for c in got]).tobytes() == free["positions"].tobytes()


def computing_threads():
    return [t for t in threading.enumerate() if t.name == "billiardkit-trajectory"]


def test_breaking_out_of_the_chunks_stops_the_computation(source):
    shape = bk.load_shape(source / "shapes" / "stadium.yaml")
    first = []
    for rows in bk.trajectory_chunks(shape, collisions=10**9, chunk=1000, progress=False):
        first.append(rows)
        if len(first) == 3:
            break
    assert computing_threads() == []  # the dropped iterator stopped and joined its thread
    whole = bk.trajectory(shape, collisions=2999)  # 3000 rows: the start and 2999 bounces
    assert np.concatenate([c["times"] for c in first]).tobytes() == whole["times"].tobytes()
    chunks = bk.trajectory_chunks(shape, collisions=10**9, chunk=1000)
    next(chunks)
    chunks.close()
    assert computing_threads() == [] and chunks.collisions is None
    with pytest.raises(StopIteration):
        next(chunks)


def test_bad_arguments_are_raised_by_the_first_chunk(source):
    chunks = bk.trajectory_chunks(scene(source, particles=3), particle=3)
    with pytest.raises(IndexError, match="particle"):
        next(chunks)
    assert computing_threads() == []


def test_ctrl_c_interrupts_iterated_chunks(source):
    """KeyboardInterrupt reaches the loop, with the computing thread stopped, within a second of
    Python's SIGINT handler running (the loop waits for chunks in steps of a tenth of a second,
    so the handler runs promptly)."""
    script = ("import billiardkit as bk, signal, sys, threading, time\n"
              "arrived = []\n"
              "def handler(sig, frame):\n"
              "    arrived.append(time.monotonic()); signal.default_int_handler(sig, frame)\n"
              "signal.signal(signal.SIGINT, handler)\n"
              f"scene = bk.Scene({str(source / 'scenes' / 'clover-driven.yaml')!r}, particles=2)\n"
              "print('started', flush=True)\n"
              "try:\n"
              "    for rows in bk.trajectory_chunks(scene, collisions=10**9, dt=0.01, progress=False):\n"
              "        pass\n"
              "except KeyboardInterrupt:\n"
              "    alive = [t for t in threading.enumerate() if t.name == 'billiardkit-trajectory']\n"
              "    print('interrupted', len(alive), time.monotonic() - arrived[0] < 1, flush=True); sys.exit(3)\n")
    assert interrupted(script) == (3, "interrupted 0 True\n")


def test_billiard_trajectory_writes_pythons_rows(source, tmp_path):
    """The CLI's chunked files hold bk.trajectory's bounces (wall >= -1) and samples (wall -2)."""
    for table, py_source, extra in [("shapes/stadium.yaml", bk.load_shape(source / "shapes" / "stadium.yaml"),
                                     dict(seed=5)),
                                    ("scenes/clover-driven.yaml", scene(source), dict())]:
        out = tmp_path / pathlib.Path(table).stem
        seed = ["--seed", "5"] if extra else []
        done = subprocess.run([BINARY, "trajectory", table, "--collisions", "300", "--dt", "0.05", "--particle", "1",
                               "--chunk", "100", "--quiet", "--out", str(out), *seed], capture_output=True, text=True,
                              cwd=source)
        assert done.returncode == 0, done.stderr
        index = json.loads((out / "trajectory.json").read_text())
        rows = np.concatenate([np.load(out / c["file"]) for c in index["chunks"]])
        assert index["columns"] == ["t", "x", "y", "vx", "vy", "wall", "energy"] and len(rows) == index["rows"]
        py = bk.trajectory(py_source, collisions=300, dt=0.05, particle=1, **extra)
        bounces, samples = rows[rows[:, 5] != -2], rows[rows[:, 5] == -2]
        assert bounces[:, 0].tobytes() == py["times"].tobytes()
        assert bounces[:, 1:3].tobytes() == py["positions"].tobytes()
        assert bounces[:, 3:5].tobytes() == py["velocities"].tobytes()
        assert np.array_equal(bounces[:, 5], py["walls"])
        assert samples[:, 0].tobytes() == py["samples"]["times"].tobytes()
        assert samples[:, 1:3].tobytes() == py["samples"]["positions"].tobytes()
        assert samples[:, 6].tobytes() == py["samples"]["energies"].tobytes()


@pytest.mark.parametrize("streamed", [False, True])
def test_ctrl_c_interrupts_a_long_trajectory(source, streamed):
    """SIGINT during a trajectory of 1e9 collisions (minutes) raises KeyboardInterrupt: the run
    checks for signals about every tenth of a second."""
    sink = ", on_chunk=lambda c: None" if streamed else ""
    script = ("import billiardkit as bk, sys, time\n"
              f"scene = bk.Scene({str(source / 'scenes' / 'clover-driven.yaml')!r}, particles=2)\n"
              "print('started', flush=True)\n"
              "try:\n"
              f"    bk.trajectory(scene, collisions=10**9, progress=False{sink})\n"
              "except KeyboardInterrupt:\n"
              "    print('interrupted', flush=True); sys.exit(3)\n")
    assert interrupted(script) == (3, "interrupted\n")


def test_ctrl_c_interrupts_a_single_long_particle(source):
    """SIGINT during `run` of two particles that each run for hours raises KeyboardInterrupt: the
    particles check for it as they go, not only between chunks of particles."""
    script = ("import billiardkit as bk, sys\n"
              f"shape = bk.load_shape({str(source / 'shapes' / 'clover.yaml')!r})\n"
              "scene = bk.Scene(shape, force={'periodic': {'amplitude': [1, 1], 'omega': 100}}, energy=0.5,\n"
              "                 particles=2, time=4e7, record=[1.0])\n"
              "print('started', flush=True)\n"
              "try:\n"
              "    bk.run(scene, threads=1, progress=False)\n"
              "except KeyboardInterrupt:\n"
              "    print('interrupted', flush=True); sys.exit(3)\n")
    assert interrupted(script) == (3, "interrupted\n")


# --- animations ----------------------------------------------------------------------------

needs_ffmpeg = pytest.mark.skipif(not shutil.which("ffprobe"), reason="ffmpeg is not installed (scripts/setup installs it)")


def frame_count(path):
    out = subprocess.run(["ffprobe", "-v", "error", "-count_frames", "-select_streams", "v:0", "-show_entries",
                          "stream=nb_read_frames,codec_name,width,height", "-of", "json", str(path)],
                         capture_output=True, text=True, check=True).stdout
    return json.loads(out)["streams"][0]


def decoded_frame(path, k, width, height):
    raw = subprocess.run(["ffmpeg", "-v", "error", "-i", str(path), "-vf", f"select=eq(n\\,{k})", "-vframes", "1",
                          "-f", "rawvideo", "-pix_fmt", "rgb24", "-"], capture_output=True, check=True).stdout
    return np.frombuffer(raw, dtype=np.uint8).reshape(height, width, 3)


@needs_ffmpeg
@pytest.mark.parametrize("ext,codec", [(".mp4", "h264"), (".gif", "gif")])
def test_animate_writes_a_movie_with_every_frame(source, tmp_path, ext, codec):
    sc = scene(source, particles=30, time=0.5)
    anim = bk.animate(sc, tmp_path / f"m{ext}", frames=12, trail=3, progress=False)
    info = frame_count(anim.path)
    assert info["codec_name"] == codec and int(info["nb_read_frames"]) == 12 == anim.frame_count
    assert (info["width"], info["height"]) == (1000, 500)  # the table and the histogram panel
    html = anim._repr_html_()
    assert html.startswith("<video" if ext == ".mp4" else "<img") and "base64," in html
    assert [p.name for p in tmp_path.iterdir()] == [f"m{ext}"]  # no temporary left


@needs_ffmpeg
def test_a_frame_shows_the_particle_where_it_is(source, tmp_path):
    """One particle: in decoded frame k, the centroid of its red marker is at the pixel its
    sampled position maps to through the table's axes."""
    sc = scene(source, name="clover-free", particles=2, time=2)
    anim = bk.animate(sc, tmp_path / "one.mp4", particles=1, frames=9, histogram=False, progress=False)
    fig, ax, _ = movie.figure(sc.shape.outline(), anim.frames, histogram=False)
    width, height = (int(round(v)) for v in fig.get_size_inches() * movie.DPI)
    assert frame_count(anim.path)["width"] == width
    red = np.array([0xd6, 0x27, 0x28])
    for k in (0, 4, 8):
        img = decoded_frame(anim.path, k, width, height).astype(int)
        mask = (np.abs(img - red).sum(axis=2) < 90)
        rows, cols = np.nonzero(mask)
        assert 3 <= len(rows) < 200, k
        px, py = ax.transData.transform(anim.frames["positions"][k, 0])
        assert abs(cols.mean() + 0.5 - px) < 1.5 and abs(rows.mean() + 0.5 - (height - py)) < 1.5, k


def test_animate_refuses_a_bad_format(source, tmp_path):
    with pytest.raises(ValueError, match=r"\.mp4 or \.gif"):
        bk.animate(scene(source, particles=3, time=0.1), tmp_path / "m.avi", frames=3, progress=False)
    assert list(tmp_path.iterdir()) == []


@needs_ffmpeg
def test_billiard_animate_writes_the_same_frames(source, tmp_path):
    out = tmp_path / "cli.mp4"
    done = subprocess.run([BINARY, "animate", "scenes/clover-driven.yaml", "-o", out, "--particles", "20", "--time",
                           "0.5", "--frames", "10", "--trail", "2", "--quiet"], capture_output=True, text=True,
                          cwd=source)
    assert done.returncode == 0, done.stderr
    assert int(frame_count(out)["nb_read_frames"]) == 10
    py = bk.animate(scene(source, particles=20, time=0.5), tmp_path / "py.mp4", frames=10, trail=2, progress=False)
    # The same scene, seed and drawing code: the same pictures.
    for k in (0, 9):
        assert np.array_equal(decoded_frame(out, k, 1000, 500), decoded_frame(py.path, k, 1000, 500)), k
