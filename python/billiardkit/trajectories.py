"""Single trajectories, collected or streamed in chunks, sampled densely along their true flights
on request; and animations of a scene's particles (billiardkit.animate, as `billiard animate`)."""
import base64
import math
import os
import queue
import threading

from . import _core
from . import movie
from .results import _progress_bar

# No limit on the number of collisions (the largest size_t).
UNLIMITED = 2**64 - 1


def _trajectory_arguments(scene_or_shape, collisions, time, dt, particle, seed, speed, chunk):
    """_core.trajectory's keyword arguments: the defaults of `trajectory` filled in."""
    if collisions is None:
        collisions = 100 if time is None else UNLIMITED
    kwargs = dict(collisions=collisions, particle=particle, dt=0.0 if dt is None else dt,
                  time=math.inf if time is None else time, chunk=chunk)
    if not isinstance(scene_or_shape, _core.Scene):
        kwargs.update(seed=seed, speed=speed)
    return kwargs


def trajectory(scene_or_shape, *, collisions=None, time=None, dt=None, particle=0, seed=1, speed=1.0,
               on_chunk=None, chunk=65536, progress=None):
    """One particle's trajectory: particle `particle` of a Scene's ensemble (the initial state `run`
    gives it), or a free particle in a Shape or Shape3 from a uniform random start (seed, speed).

    It runs for `collisions` bounces or up to `time`, whichever comes first (collisions=None: 100
    without a time, no limit with one).  Returns a dict: times (K+1,), positions and velocities
    (K+1, d) just after each bounce, walls (K+1,) (the start: -1), escaped, and samples: with dt,
    the states at t0, t0 + dt, ... between the bounces, along the flight's true (curved) path,
    as times, positions, velocities, energies; None without dt.

    on_chunk: streams instead of collecting: on_chunk(rows) is called with a dict of the same keys
    for at most `chunk` bounces and samples at a time, nothing is kept (a run of 1e9 collisions
    needs the memory of one chunk), and the result is {collisions, escaped}.  trajectory_chunks
    streams the same chunks as an iterator.
    progress: True for a tqdm bar, False for none, None for a bar on a terminal or in Jupyter
    when tqdm is installed.  Ctrl-C raises KeyboardInterrupt within a tenth of a second."""
    kwargs = _trajectory_arguments(scene_or_shape, collisions, time, dt, particle, seed, speed, chunk)
    by_time = time is not None
    bar = _progress_bar(time if by_time else kwargs["collisions"], progress, unit="time" if by_time else "collision",
                        desc="trajectory")
    if bar is None:
        return _core.trajectory(scene_or_shape, on_chunk=on_chunk, **kwargs)
    with bar:
        def update(done, t):
            bar.update((t if by_time else done) - bar.n)
        return _core.trajectory(scene_or_shape, on_chunk=on_chunk, progress=update, **kwargs)


class _Stopped(Exception):
    """Raised in the computing thread to end its trajectory when the iterator is closed."""


class _Stream:
    """What the thread computing a trajectory shares with its TrajectoryChunks: a queue of at most
    one finished chunk, and a stop flag that the thread sees within a tenth of a second (at its
    next heartbeat or while it waits to hand over a chunk).  It holds no reference to the
    iterator, so that an iterator the consumer drops (a `break`) is closed and stops the thread."""

    def __init__(self):
        self.queue = queue.Queue(maxsize=1)
        self.stop = threading.Event()

    def put(self, item):
        while not self.stop.is_set():
            try:
                return self.queue.put(item, timeout=0.1)
            except queue.Full:
                pass
        raise _Stopped

    def heartbeat(self, collisions, t):
        if self.stop.is_set():
            raise _Stopped

    def produce(self, scene_or_shape, kwargs):
        try:
            item = ("end", _core.trajectory(scene_or_shape, on_chunk=lambda rows: self.put(("rows", rows)),
                                            progress=self.heartbeat, **kwargs))
        except _Stopped:
            return
        except BaseException as e:  # handed to the consumer, raised by its next()
            item = ("error", e)
        try:
            self.put(item)
        except _Stopped:
            pass


class TrajectoryChunks:
    """An iterator of a trajectory's chunks (see trajectory_chunks).  After the last chunk its
    `collisions`, `escaped` and `trapped` are set (None before).  close() (or leaving a `with`
    block, or dropping the iterator) stops the computation."""

    def __init__(self, scene_or_shape, kwargs, bar, by_time):
        self.collisions = self.escaped = self.trapped = None
        self._stream = _Stream()
        self._bar, self._by_time, self._done = bar, by_time, 0
        self._closed = False
        self._thread = threading.Thread(target=self._stream.produce, args=(scene_or_shape, kwargs),
                                        name="billiardkit-trajectory", daemon=True)
        self._thread.start()

    def __iter__(self):
        return self

    def __next__(self):
        if self._closed:
            raise StopIteration
        try:
            kind, item = self._get()
        except BaseException:  # KeyboardInterrupt
            self.close()
            raise
        if kind == "rows":
            self._advance(item)
            return item
        self.close()
        if kind == "error":
            raise item
        self.collisions, self.escaped, self.trapped = item["collisions"], item["escaped"], item["trapped"]
        raise StopIteration

    def _get(self):
        """The next item, waiting in steps of a tenth of a second so that Ctrl-C is seen."""
        while True:
            try:
                return self._stream.queue.get(timeout=0.1)
            except queue.Empty:
                pass

    def _advance(self, rows):
        if self._bar is None:
            return
        if self._by_time:
            samples = rows["samples"]
            last = rows["times"][-1] if samples is None or not len(samples["times"]) \
                else max(rows["times"][-1], samples["times"][-1])
            self._bar.update(last - self._bar.n)
        else:
            self._done += len(rows["times"])
            self._bar.update(self._done - 1 - self._bar.n)  # (the first chunk's first row is the start)

    def close(self):
        if self._closed:
            return
        self._closed = True
        self._stream.stop.set()
        self._thread.join()
        if self._bar is not None:
            self._bar.close()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    def __del__(self):
        if hasattr(self, "_thread"):
            self.close()


def trajectory_chunks(scene_or_shape, *, collisions=None, time=None, dt=None, particle=0, seed=1, speed=1.0,
                      chunk=65536, progress=None):
    """The trajectory of `trajectory` (same arguments and numbers) as an iterator of chunks: each a
    dict of the keys trajectory returns, with at most `chunk` bounces and `chunk` samples; the
    chunks concatenated are trajectory's arrays, bit for bit.

        for rows in bk.trajectory_chunks(scene, collisions=10**9, dt=0.01):
            ...

    A thread computes the next chunk with the GIL released while the consumer handles this one;
    at most three chunks exist at a time, so a run of 1e9 collisions needs bounded memory.
    Ctrl-C raises KeyboardInterrupt within a tenth of a second; a `break` (or close(), or a
    `with` block's end) stops the computation.  An error in the arguments is raised by the first
    next().  After the last chunk, the iterator's collisions, escaped and trapped are set."""
    kwargs = _trajectory_arguments(scene_or_shape, collisions, time, dt, particle, seed, speed, chunk)
    by_time = time is not None
    bar = _progress_bar(time if by_time else kwargs["collisions"], progress, unit="time" if by_time else "collision",
                        desc="trajectory")
    return TrajectoryChunks(scene_or_shape, kwargs, bar, by_time)


class Animation:
    """A movie written by billiardkit.animate: its path, frame count and frames (the dict of
    positions and energies it shows).  In Jupyter it plays inline (_repr_html_)."""

    def __init__(self, path, frames):
        self.path = os.fspath(path)
        self.frames = frames

    @property
    def frame_count(self):
        return len(self.frames["times"])

    def _repr_html_(self):
        with open(self.path, "rb") as f:
            data = base64.b64encode(f.read()).decode("ascii")
        if self.path.lower().endswith(".gif"):
            return f'<img src="data:image/gif;base64,{data}"/>'
        return f'<video controls loop src="data:video/mp4;base64,{data}"></video>'

    def __repr__(self):
        return f"<billiardkit.Animation '{self.path}': {self.frame_count} frames>"


def animate(scene, output, *, particles=None, time=None, frames=250, fps=25, trail=0, histogram=None, threads=0,
            progress=None):
    """Writes a movie of a 2-D scene's particles moving in its table (output: .mp4 through ffmpeg,
    .gif through Pillow or ffmpeg), as `billiard animate` does, and returns an Animation.

    particles: the first N particles of the scene's ensemble (default: up to 100).  time: the
    movie shows t = 0 .. time (default: the scene's end time) in `frames` frames at uniform times,
    played at `fps` frames a second.  Each frame shows the particles' exact states, sampled along
    their true flights (curved for a driven particle).  trail: frames of path drawn behind each
    particle.  histogram: the side panel with the energy histogram against the Fokker-Planck
    density (None: when the theory covers the scene).  progress: as for `run`."""
    if scene.dimension != 2:
        raise ValueError("animate draws 2-D scenes; this scene is 3-D")
    particles = min(scene.particles, 100) if particles is None else particles
    time = scene.time if time is None else time
    bar = _progress_bar(particles, progress, unit="particle", desc="animate")
    update = None if bar is None else (lambda done, total: bar.update(done - bar.n))
    try:
        data = _core.frames(scene, particles=particles, frames=frames, time=time, threads=threads, progress=update)
    finally:
        if bar is not None:
            bar.close()
    title = f"{os.path.splitext(os.path.basename(scene.file))[0] or 'scene'}: N = {particles}"
    movie.write_movie(scene.shape.outline(), data, output, fps=fps, trail=trail, histogram=histogram, title=title)
    return Animation(output, data)
