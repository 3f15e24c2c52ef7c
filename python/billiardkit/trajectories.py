"""Single trajectories, collected or streamed in chunks, sampled densely along their true flights
on request; and animations of a scene's particles (billiardkit.animate, as `billiard animate`)."""
import base64
import math
import os

from . import _core
from . import movie
from .results import _progress_bar

# No limit on the number of collisions (the largest size_t).
UNLIMITED = 2**64 - 1


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
    needs the memory of one chunk), and the result is {collisions, escaped}.
    progress: True for a tqdm bar, False for none, None for a bar on a terminal or in Jupyter
    when tqdm is installed.  Ctrl-C raises KeyboardInterrupt within a tenth of a second."""
    if collisions is None:
        collisions = 100 if time is None else UNLIMITED
    kwargs = dict(collisions=collisions, particle=particle, dt=0.0 if dt is None else dt,
                  time=math.inf if time is None else time, on_chunk=on_chunk, chunk=chunk)
    if not isinstance(scene_or_shape, _core.Scene):
        kwargs.update(seed=seed, speed=speed)
    by_time = time is not None
    bar = _progress_bar(time if by_time else collisions, progress, unit="time" if by_time else "collision",
                        desc="trajectory")
    if bar is None:
        return _core.trajectory(scene_or_shape, **kwargs)
    with bar:
        def update(done, t):
            bar.update((t if by_time else done) - bar.n)
        return _core.trajectory(scene_or_shape, progress=update, **kwargs)


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
