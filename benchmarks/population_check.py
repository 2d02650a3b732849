"""Does the population model describe a region it never saw?
``roughgp.experiments.population_check.population_case`` on synthetic parts of known
populations (issue 40, item 3: the hierarchical model; about 10 % outside per parameter for a
model that describes the part).

Each case (6 regions of a part fitted, a seventh checked against eq 18 of one region, eq 18
of all six, the population model and the truth) is appended to
``benchmarks/results/population_check.jsonl`` as it ends (a case already there is skipped: a
run can be resumed); ``--report`` writes ``benchmarks/results/population_check.md`` and prints
it. The cases run on the project's engine (:func:`roughgp.batch.engine.run_cases`: a local Dask
cluster, one BLAS thread per worker, or ``--scheduler ADDRESS``). Not a test: run it by hand,

    python benchmarks/population_check.py --cases 50 --workers 2   # about 20 minutes on 2 cores
    python benchmarks/population_check.py --report
"""

from __future__ import annotations

import argparse
import datetime
from pathlib import Path

from roughgp.batch.engine import (
    add_cluster_options,
    appending_records,
    on_one_thread,
    run_cases,
)
from roughgp.common.atomic import atomic_output
from roughgp.experiments.population_check import (
    KINDS,
    MODELS,
    RECORDED,
    REGIONS,
    load_records,
    population_case,
    shares_markdown,
)


def report(records) -> str:
    """The Markdown report of the recorded cases."""
    minutes = sum(r["seconds"] for r in records) / 60
    lines = [f"# The population model on a region it never saw ({datetime.date.today()})", "",
             f"From `{RECORDED.name}`: {len(records)} cases, {minutes:.0f} CPU minutes. Each "
             f"case: {REGIONS} regions of a synthetic part fitted (64 x 64 points each), a "
             f"seventh checked with 19 simulations. Share of the cases with the parameter "
             f"outside the simulated range (10 % for a model that describes the part):", "",
             shares_markdown(records)]
    return "\n".join(lines) + "\n"


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--cases", type=int, default=50, help="cases of each kind (default 50)")
    parser.add_argument("--kinds", nargs="+", default=list(KINDS), choices=KINDS)
    add_cluster_options(parser)
    parser.add_argument("--out", type=Path, default=RECORDED)
    parser.add_argument("--report", action="store_true", help="write and print the table")
    args = parser.parse_args(argv)
    if args.report:
        text = report(load_records(args.out))
        with atomic_output(args.out.with_suffix(".md")) as partial:
            Path(partial).write_text(text)
        print(text)
        return 0
    done = {(r["kind"], r["index"]) for r in load_records(args.out)}
    todo = [(kind, index) for index in range(args.cases) for kind in args.kinds
            if (kind, index) not in done]
    print(f"{len(todo)} case(s) to run, {len(done)} recorded", flush=True)
    record = appending_records(args.out, lambda r: "; ".join(
        f"{m} {len(r['outside'][m])}" for m in MODELS) + f" ({r['seconds']:.0f} s)", len(todo))
    run_cases(on_one_thread, [(f"{kind} {index}", (population_case, kind, index),
                               f"population-{kind}-{index}") for kind, index in todo],
              workers=args.workers, scheduler=args.scheduler, on_result=record)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
