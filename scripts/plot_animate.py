#!/usr/bin/python3
"""Draws the movie of `billiard animate` from the frames it computed.

    plot_animate.py INPUT_DIR OUTPUT.mp4|OUTPUT.gif [--progress]

INPUT_DIR: movie.json {"outline": [[[x, y], ...], ...] (outer loop first), "title", "fps",
"trail"}, times.npy (K x 1), positions.npy (K x 2N), energies.npy (K x N) and, for the
histogram panel, fp_energies.npy (cells x 1) and fp_density.npy (K-1 x cells).  The drawing is
billiardkit's movie.py (the same as billiardkit.animate), found beside this script when
installed or in the source tree's python/billiardkit.  --progress: a frame counter on stdout.
"""
import importlib.util
import json
import pathlib
import sys

try:
    import matplotlib
    import numpy as np
except ImportError:
    sys.exit("plot_animate.py: matplotlib or numpy is missing (Debian: apt install python3-matplotlib)")
matplotlib.use("Agg")

HERE = pathlib.Path(__file__).resolve().parent


def movie_module():
    for path in (HERE / "movie.py", HERE.parent / "python" / "billiardkit" / "movie.py"):
        if path.is_file():
            spec = importlib.util.spec_from_file_location("billiard_movie", path)
            module = importlib.util.module_from_spec(spec)
            spec.loader.exec_module(module)
            return module
    sys.exit(f"plot_animate.py: movie.py not found beside {HERE} or in the source tree")


def main():
    folder, output = pathlib.Path(sys.argv[1]), sys.argv[2]
    meta = json.loads((folder / "movie.json").read_text())
    energies = np.load(folder / "energies.npy")
    K, N = energies.shape
    frames = {"times": np.load(folder / "times.npy")[:, 0], "positions": np.load(folder / "positions.npy").reshape(K, N, 2),
              "energies": energies, "fp_energies": None, "fp_density": None}
    if (folder / "fp_density.npy").is_file():
        frames["fp_energies"] = np.load(folder / "fp_energies.npy")[:, 0]
        frames["fp_density"] = np.load(folder / "fp_density.npy")

    def progress(done, total):
        print(f"\rdrawing [{'#' * (30 * done // total):<30}] {done}/{total}", end="" if done < total else "\n",
              flush=True)

    movie_module().write_movie(meta["outline"], frames, output, fps=meta["fps"], trail=meta["trail"],
                               title=meta["title"], progress=progress if "--progress" in sys.argv[3:] else None)


if __name__ == "__main__":
    main()
