"""Figure 7 under several numerical set-ups: which optimum the fits of eq 22 reach, and what the
simulations from it show, when the optimiser's starts are moved by 1e-6 (the start jitter of
:mod:`roughgp.common.numerics`, seeds 0 .. 7; seed 0 is the unperturbed run).

Each set-up runs :func:`roughgp.experiments.turned_surface.turned_surface_flaw` with
``careful=True`` at the chapter's quick size in a fresh process (no results cache), and writes
one :func:`~roughgp.experiments.turned_surface.optima_record` per line to
``benchmarks/results/turned_surface_optima.jsonl``, which the chapter "Turned surfaces" reads
(:func:`~roughgp.experiments.turned_surface.summarise_optima`). Two set-ups run at a time, each
on one BLAS thread. A run takes 2-5 minutes per set-up on the 2-core machine:

    python benchmarks/turned_surface_optima.py                  # seeds 0..7, 2 at a time
    python benchmarks/turned_surface_optima.py --seeds 0 1 --jobs 1 --out /tmp/optima.jsonl
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from roughgp.common.atomic import atomic_output
from roughgp.experiments import turned_surface
from roughgp.ledger.setups import Setup


def child(seed: int, out: Path) -> None:
    """In the set-up's own process: the careful run, its record written to ``out``."""
    result = turned_surface.turned_surface_flaw(False, careful=True)
    out.write_text(json.dumps(turned_surface.optima_record(result, seed)))


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", nargs="+", type=int, default=list(range(8)),
                        help="start jitter seeds (default 0..7; 0: unperturbed)")
    parser.add_argument("--jobs", type=int, default=2, help="set-ups at a time (default 2)")
    parser.add_argument("--out", type=Path, default=turned_surface.OPTIMA_RECORDED,
                        help="the JSON-lines record (default: the chapter's)")
    parser.add_argument("--child", nargs=2, metavar=("SEED", "FILE"), help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.child:
        child(int(args.child[0]), Path(args.child[1]))
        return
    records, start = {}, time.perf_counter()
    with tempfile.TemporaryDirectory() as folder:
        waiting, running = list(args.seeds), []
        while waiting or running:
            while waiting and len(running) < args.jobs:
                seed = waiting.pop(0)
                out = Path(folder) / f"seed-{seed}.json"
                command = [sys.executable, __file__, "--child", str(seed), str(out)]
                running.append((seed, out, subprocess.Popen(
                    command, env=Setup(1, seed).environment())))
            seed, out, process = running.pop(0)
            if process.wait() != 0:
                raise SystemExit(f"set-up with start jitter {seed} failed")
            records[seed] = json.loads(out.read_text())
            r = records[seed]
            print(f"seed {seed}: log ML paper {r['paper_log_ml']:.0f}, careful "
                  f"{r['careful_log_ml']:.0f}; periodicity at the last feed paper "
                  f"{r['paper']['periodicity'][-1]:.2f}, careful "
                  f"{r['careful']['periodicity'][-1]:.2f}; short share paper "
                  f"{r['paper']['short_share']:.4f}, careful {r['careful']['short_share']:.4f} "
                  f"({time.perf_counter() - start:.0f} s)", flush=True)
    with atomic_output(args.out) as path:
        Path(path).write_text("".join(json.dumps(records[s]) + "\n" for s in sorted(records)))
    print(turned_surface.summarise_optima(records[s] for s in sorted(records)))


if __name__ == "__main__":
    main()
