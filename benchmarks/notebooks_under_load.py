"""Each chapter's quick path beside two busy processes (issue 38: "each notebook's quick path
under 300 s with two busy processes beside it"), far from nbmake's cell timeout of 900 s.

Each notebook is executed whole by nbclient in its own folder (as nbmake and the book build run
it), without the notebook cache and without the results cache (so it computes everything
itself: the worst case, as on a fresh clone where it runs first), on one BLAS thread (as the
tests run it), while two pure-Python processes burn a CPU each. Prints the seconds per notebook
and whether it stays under the bound. Not a test; run it by hand:

    python benchmarks/notebooks_under_load.py                       # the six longest chapters
    python benchmarks/notebooks_under_load.py book/claims.ipynb --quiet
"""

from __future__ import annotations

import argparse
import multiprocessing
import os
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
BOUND = 300.0
LONGEST = ("book/claims.ipynb", "book/measured_surfaces.ipynb", "book/spurious_points.ipynb",
           "book/posterior.ipynb", "book/model_ladder.ipynb", "book/gp_model.ipynb")


def execute(path: Path) -> float:
    """Wall seconds of one whole execution of ``path`` (raises if a cell fails)."""
    import nbformat
    from nbclient import NotebookClient

    notebook = nbformat.read(path, as_version=4)
    client = NotebookClient(notebook, timeout=900, kernel_name="python3",
                            resources={"metadata": {"path": str(path.parent)}})
    start = time.perf_counter()
    client.execute()
    return time.perf_counter() - start


def main():
    from under_load import NEIGHBOURS, _burn

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("notebooks", nargs="*", default=LONGEST,
                        help="notebooks (default: the six longest chapters)")
    parser.add_argument("--quiet", action="store_true", help="no busy neighbours")
    args = parser.parse_args()
    os.environ.pop("ROUGHGP_RESULTS_CACHE", None)
    for name in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
        os.environ[name] = "1"                       # as the tests run each notebook
    neighbours = []
    if not args.quiet:
        context = multiprocessing.get_context("spawn")
        neighbours = [context.Process(target=_burn, args=(3600.0,), daemon=True)
                      for _ in range(NEIGHBOURS)]
        for p in neighbours:
            p.start()
        time.sleep(1.0)
    print(f"{os.cpu_count()} CPUs; {len(neighbours)} busy neighbours; bound {BOUND:.0f} s")
    try:
        for name in args.notebooks:
            seconds = execute(ROOT / name)
            print(f"{name:<34} {seconds:7.1f} s  {'within' if seconds < BOUND else 'OVER'}",
                  flush=True)
    finally:
        for p in neighbours:
            p.terminate()
            p.join()


if __name__ == "__main__":
    import sys

    sys.path.insert(0, str(Path(__file__).resolve().parent))
    main()
