"""Benchmark of ``roughgp fill`` on a small map while two other processes keep the cores busy
(issue 18: "a small map fills in seconds while two other processes keep both cores busy").

The map: a 64 x 96 ground surface of eq 18 plus eq 8's noise (``surfaces.ground``, seeded),
1 % of its points set to NaN at seeded random places, saved as ``.npy`` in a temporary folder.
Each case runs the command ``roughgp fill MAP --out FILLED --seed 0`` as a subprocess (the
whole command: start-up, reading, the eq 18 fit on the measured points, the fill) and
measures its wall time, once on the machine as it is ("quiet") and once while two
neighbour processes burn a CPU each ("busy": pure-Python loops, started before and ended,
by their process ids, after the command). Prints the times side by side. Not a test: run it
by hand,

    python benchmarks/fill_busy.py                   # default method (local), 1 repeat
    python benchmarks/fill_busy.py --method global --repeats 3
"""

from __future__ import annotations

import argparse
import math
import multiprocessing
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from roughgp.models import surfaces

SHAPE = (64, 96)
HOLES = 0.01
NEIGHBOURS = 2


def small_map(seed: int = 3) -> np.ndarray:
    """A 64 x 96 ground surface (eq 18: sigma_k^2 = 1, lambda = 12 / 3 grid units, phi = 30
    deg, plus noise 0.05) with 1 % of its points missing (NaN), from ``seed``."""
    z = surfaces.ground(SHAPE, variance=1.0, lengthscales=(12.0, 3.0), angle=math.pi / 6,
                        noise_variance=0.05, seed=seed)
    holes = np.random.default_rng(seed + 1).random(SHAPE) < HOLES
    z[holes] = np.nan
    return z


def _burn(stop_after: float) -> None:  # pragma: no cover - runs in a child process
    """Keep one CPU busy (pure Python, no threads) for at most ``stop_after`` seconds."""
    end, x = time.monotonic() + stop_after, 1.0
    while time.monotonic() < end:
        for _ in range(100_000):
            x = x * 1.0000001 + 1e-9


def time_fill(path: Path, out: Path, method: str) -> tuple[float, str]:
    """Wall time of one ``roughgp fill`` command and its own account of the fit's and the
    fill's seconds (raises if it fails)."""
    command = [sys.executable, "-m", "roughgp.cli.main", "fill", str(path), "--out", str(out),
               "--seed", "0", "--method", method, "--force"]
    start = time.perf_counter()
    done = subprocess.run(command, capture_output=True, text=True, check=False,
                          env={**os.environ, "PYTHONPATH": str(Path(__file__).resolve().parents[1])
                               + os.pathsep + os.environ.get("PYTHONPATH", "")})
    seconds = time.perf_counter() - start
    if done.returncode != 0:
        raise RuntimeError(f"roughgp fill failed ({done.returncode}): {done.stderr[-2000:]}")
    parts = [line.split(": ")[0] if line.startswith("eq 18 fitted") else line.split(" (")[0]
             for line in done.stderr.splitlines()
             if line.startswith(("eq 18 fitted", "filled in"))]
    return seconds, "; ".join(parts)


def time_busy(path: Path, out: Path, method: str, limit: float) -> tuple[float, str]:
    """The same command while :data:`NEIGHBOURS` processes burn a CPU each; the neighbours
    are ended by their process ids afterwards."""
    context = multiprocessing.get_context("spawn")
    neighbours = [context.Process(target=_burn, args=(limit,), daemon=True)
                  for _ in range(NEIGHBOURS)]
    for p in neighbours:
        p.start()
    time.sleep(1.0)                                     # let them take the cores
    try:
        return time_fill(path, out, method)
    finally:
        for p in neighbours:
            p.terminate()
            p.join()


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--method", choices=("local", "global"), default="local",
                        help="roughgp fill --method (default local, the command's default)")
    parser.add_argument("--repeats", type=int, default=1, help="runs per case (default 1)")
    parser.add_argument("--limit", type=float, default=600.0,
                        help="the neighbours stop after this many seconds at the latest")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as folder:
        path, out = Path(folder) / "map.npy", Path(folder) / "filled.npy"
        z = small_map()
        np.save(path, z)
        print(f"map {SHAPE[0]} x {SHAPE[1]}, {np.isnan(z).sum()} missing "
              f"({np.isnan(z).mean():.1%}); roughgp fill --method {args.method}; "
              f"{os.cpu_count()} CPUs, load average {os.getloadavg()[0]:.2f} before")
        quiet = [time_fill(path, out, args.method) for _ in range(args.repeats)]
        busy = [time_busy(path, out, args.method, args.limit) for _ in range(args.repeats)]
    print(f"{'run':>4} {'quiet [s]':>10} {f'{NEIGHBOURS} busy neighbours [s]':>26}")
    for i, ((q, q_parts), (b, b_parts)) in enumerate(zip(quiet, busy)):
        print(f"{i + 1:>4} {q:>10.1f} {b:>26.1f}")
        print(f"     quiet: {q_parts}\n     busy:  {b_parts}")
    ratio = np.median([b for b, _ in busy]) / np.median([q for q, _ in quiet])
    print(f"slow-down with busy neighbours: {ratio:.1f}x (median of {args.repeats})")


if __name__ == "__main__":
    main()
