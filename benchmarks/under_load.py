"""The three timing targets of issue 38 ("nothing melts under load"), each run as a whole
``roughgp`` command on this machine as it is ("quiet") and while two neighbour processes keep
a CPU busy each ("busy": pure-Python loops, started before the command and ended after it).

The commands and their bounds under load:

* ``roughgp simulate honed --shape 64 64``: under 2 s (figure 3's surface, the block Levinson
  recursion of :mod:`roughgp.sampling.block_levinson`);
* ``roughgp fill`` of a 256 x 256 crop of a real map (``data/opd-1.opd``, rows and columns
  0:256) with 2 % of its points removed in seeded discs (1.5 to 4 points in radius): under
  90 s (the eq 18 block fit, the self-check and the local kriging windows);
* ``roughgp fit ground --model auto`` of a 512 x 512 map (``data/nms-1.nms``): under 120 s
  (four rungs fitted and judged on held-out discs).

Prints one line per command and case with the wall time (median over ``--repeats``), the
busy/quiet ratio and whether the bound holds. Not a test (timings belong in benchmarks, not in
asserts); run it by hand and record what it prints in ``benchmarks/results/``:

    python benchmarks/under_load.py                    # all three, 1 repeat each
    python benchmarks/under_load.py --only honed fill --repeats 3
"""

from __future__ import annotations

import argparse
import multiprocessing
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
NEIGHBOURS = 2
BOUNDS = {"honed": 2.0, "fill": 90.0, "auto": 120.0}   # seconds, with two busy neighbours


def _burn(stop_after: float) -> None:  # pragma: no cover - runs in a child process
    """Keep one CPU busy (pure Python, no threads) for at most ``stop_after`` seconds."""
    end, x = time.monotonic() + stop_after, 1.0
    while time.monotonic() < end:
        for _ in range(100_000):
            x = x * 1.0000001 + 1e-9


def holed_crop(folder: Path, seed: int = 0) -> Path:
    """The 256 x 256 crop of ``data/opd-1.opd`` with 2 % of its points in seeded discs set
    missing, written as ``.x3p`` (the file's spacing kept); returns its path."""
    from roughgp.io.measurement import read_measurement
    from roughgp.io.x3p import write_x3p

    measured = read_measurement(ROOT / "data" / "opd-1.opd")
    z = np.array(measured.z[:256, :256], dtype=np.float64)
    rng = np.random.default_rng(seed)
    rows, columns = np.mgrid[:256, :256]
    holes = np.zeros(z.shape, dtype=bool)
    while holes.mean() < 0.02:
        cy, cx = rng.integers(0, 256, 2)
        radius = rng.uniform(1.5, 4.0)
        holes |= (rows - cy) ** 2 + (columns - cx) ** 2 <= radius ** 2
    z[holes] = np.nan
    path = folder / "opd-1-crop256-holes.x3p"
    write_x3p(path, z, measured.spacing)
    return path


def commands(folder: Path) -> dict[str, list[str]]:
    """The three commands (as argument lists after ``roughgp``), writing into ``folder``."""
    return {
        "honed": ["simulate", "honed", "--shape", "64", "64", "--seed", "0",
                  "--out", str(folder / "honed.npy"), "--force"],
        "fill": ["fill", str(holed_crop(folder)), "--out", str(folder / "filled.npy"),
                 "--seed", "0", "--force"],
        "auto": ["fit", "ground", str(ROOT / "data" / "nms-1.nms"), "--model", "auto",
                 "--out", str(folder / "auto.json"), "--force"],
    }


def time_command(arguments: list[str]) -> float:
    """Wall seconds of one ``roughgp ARGUMENTS`` process (raises if it fails)."""
    command = [sys.executable, "-m", "roughgp.cli.main", *arguments]
    start = time.perf_counter()
    done = subprocess.run(command, capture_output=True, text=True, check=False, cwd=ROOT)
    seconds = time.perf_counter() - start
    if done.returncode != 0:
        raise RuntimeError(f"roughgp {' '.join(arguments)} failed ({done.returncode}): "
                           f"{done.stderr[-2000:]}")
    return seconds


def time_busy(arguments: list[str], limit: float) -> float:
    """:func:`time_command` while :data:`NEIGHBOURS` processes burn a CPU each."""
    context = multiprocessing.get_context("spawn")
    neighbours = [context.Process(target=_burn, args=(limit,), daemon=True)
                  for _ in range(NEIGHBOURS)]
    for p in neighbours:
        p.start()
    time.sleep(1.0)                                     # let them take the cores
    try:
        return time_command(arguments)
    finally:
        for p in neighbours:
            p.terminate()
            p.join()


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--only", nargs="+", choices=tuple(BOUNDS), default=tuple(BOUNDS),
                        help="the commands to time (default: all three)")
    parser.add_argument("--repeats", type=int, default=1, help="runs per case (default 1)")
    parser.add_argument("--busy-only", action="store_true",
                        help="skip the quiet runs (the bounds are for the busy case)")
    parser.add_argument("--limit", type=float, default=900.0,
                        help="the neighbours stop after this many seconds at the latest")
    args = parser.parse_args()
    threads = {k: v for k, v in os.environ.items()
               if k.endswith("_NUM_THREADS") or k.startswith("OPENBLAS_")}
    print(f"{os.cpu_count()} CPUs, load average {os.getloadavg()[0]:.2f} before; "
          f"environment: {threads or 'no thread or OpenBLAS variables'}")
    print(f"{'command':>7} {'quiet [s]':>10} {f'{NEIGHBOURS} busy [s]':>11} {'ratio':>6} "
          f"{'bound [s]':>9}  within")
    with tempfile.TemporaryDirectory() as folder:
        table = commands(Path(folder))
        for name in args.only:
            quiet = (None if args.busy_only else
                     statistics.median(time_command(table[name]) for _ in range(args.repeats)))
            busy = statistics.median(time_busy(table[name], args.limit)
                                     for _ in range(args.repeats))
            ratio = "-" if quiet is None else f"{busy / quiet:.1f}"
            quiet_text = "-" if quiet is None else f"{quiet:.1f}"
            print(f"{name:>7} {quiet_text:>10} {busy:>11.1f} {ratio:>6} {BOUNDS[name]:>9.0f}  "
                  f"{'yes' if busy < BOUNDS[name] else 'NO'}", flush=True)


if __name__ == "__main__":
    main()
