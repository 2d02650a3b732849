"""Benchmark of ``roughgp batch``'s engine (issue 42: "with 2 local workers at least 1.7x faster
than with 1 on this 2-core machine"): the maps of ``data/`` (every file that reads as a
surface) through texture and fit (eq 18, the default), once on a Dask ``LocalCluster`` of 1
worker and once of 2, side by side in one run, each into a fresh output folder and timed
whole (the cluster's start, the workers' imports, every file, the table). It prints both wall
times, their ratio, the sum of the files' own times in each (the work, whatever the workers),
the 1-minute load average before and after each, and whether the two tables agree number for
number (they must: each file's seed comes from its bytes). Not a test: run it by hand at the
repository root,

    python benchmarks/batch_workers.py                      # texture + fit of every map
    python benchmarks/batch_workers.py --steps texture      # the quick part only
    python benchmarks/batch_workers.py --workers 1 2 --order 2 1   # the larger run first

The figures depend on what else runs on the machine (the load average is printed): on a
2-core machine shared with other work, 2 workers compete with it for the cores.
"""

from __future__ import annotations

import argparse
import os
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

os.environ.setdefault("OMP_NUM_THREADS", "1")


def maps(folder: Path) -> list:
    """The files of ``folder`` that read as surfaces (the maps), sorted."""
    import roughgp
    from roughgp.batch.engine import expand_inputs
    found = []
    for path in expand_inputs([folder]):
        try:
            if roughgp.read(path).kind == "surface":
                found.append(path)
        except Exception:  # noqa: BLE001 - no measurement: not a map
            pass
    return found


def _load() -> float:
    return os.getloadavg()[0]


def one_run(files, steps, workers) -> dict:
    from roughgp.batch.engine import run_batch
    from roughgp.batch.records import Plan
    from roughgp.batch.table import read_csv_table
    plan = Plan(steps=tuple(steps), seed=0)
    with tempfile.TemporaryDirectory(prefix=f"batch-{workers}w-") as out:
        load = _load()
        start = time.perf_counter()
        result = run_batch(files, plan, out, workers=workers)
        wall = time.perf_counter() - start
        table = [{k: v for k, v in row.items() if not k.startswith("seconds.")}
                 for row in read_csv_table(Path(out) / "table.csv")]
    times = [(r.get("seconds") or {}).get("total", 0.0) for r in result.records]
    return {"workers": workers, "wall": wall, "work": sum(times), "longest": max(times),
            "failed": result.failed,
            "load_before": load, "load_after": _load(), "table": table}


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--folder", default=str(ROOT / "data"))
    parser.add_argument("--steps", default="texture,fit")
    parser.add_argument("--order", type=int, nargs="+", default=[1, 2],
                        help="the worker counts, run in this order (default 1 2)")
    args = parser.parse_args(argv)
    files = maps(Path(args.folder))
    steps = args.steps.split(",")
    print(f"{len(files)} maps of {args.folder}, steps {','.join(steps)}; "
          f"{os.cpu_count()} cores; load average {os.getloadavg()}")
    runs = {}
    for workers in args.order:
        run = one_run(files, steps, workers)
        runs[workers] = run
        print(f"  {workers} worker{'s' * (workers != 1)}: {run['wall']:7.1f} s wall, "
              f"{run['work']:7.1f} s of file time, {run['failed']} failed; load "
              f"{run['load_before']:.2f} before, {run['load_after']:.2f} after", flush=True)
    if 1 in runs and 2 in runs:
        ratio = runs[1]["wall"] / runs[2]["wall"]
        print(f"speed-up of 2 workers over 1: {ratio:.2f}x (target 1.7x on 2 cores)")
        one = runs[1]
        best = one["wall"] / max(one["work"] / 2 + (one["wall"] - one["work"]), one["longest"])
        print(f"  the longest file took {one['longest']:.1f} s of the 1-worker run's "
              f"{one['work']:.1f} s: 2 workers can do at most {best:.2f}x (half the files' "
              f"time plus the rest, or the longest file)")
        same = runs[1]["table"] == runs[2]["table"]
        print(f"tables of 1 and 2 workers the same number for number: {same}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
