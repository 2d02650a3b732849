"""Does the eq18-field model recover the parameter fields of known non-stationary surfaces, and
does it pass the tile check where eq 18 fails? ``roughgp.experiments.field_recovery.field_case``
on synthetic 256 x 256 maps of four kinds (issue 40, items 3 and 4).

Each case is appended to ``benchmarks/results/field_recovery.jsonl`` as it comes (a case
already there is skipped: a run can be resumed); ``--report`` writes the Markdown table
``benchmarks/results/field_recovery.md`` and prints it. The cases run on the project's engine
(:func:`roughgp.batch.engine.run_cases`: a local Dask cluster, one BLAS thread per worker, or
``--scheduler ADDRESS``). Not a test: run it by hand,

    python benchmarks/field_recovery.py --cases 10 --workers 2   # 10 of each kind
    python benchmarks/field_recovery.py --report
"""

from __future__ import annotations

import argparse
import datetime
from pathlib import Path

from roughgp.batch.engine import add_cluster_options, appending_records, run_cases
from roughgp.common.atomic import atomic_output
from roughgp.experiments.field_recovery import KINDS, RECORDED, load_records, recovery_table


def _run_case(kind, index, seed):
    from threadpoolctl import threadpool_limits

    from roughgp.experiments.field_recovery import field_case
    with threadpool_limits(1):
        return field_case(kind, index, seed=seed)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--cases", type=int, default=10, help="cases of each kind (default 10)")
    parser.add_argument("--kinds", nargs="+", choices=KINDS, default=None,
                        help="kinds (default: all)")
    parser.add_argument("--seed", type=int, default=0)
    add_cluster_options(parser)
    parser.add_argument("--out", type=Path, default=RECORDED)
    parser.add_argument("--report", action="store_true", help="write and print the table")
    args = parser.parse_args(argv)
    if args.report:
        records = load_records(args.out)
        minutes = sum(r["seconds"] for r in records) / 60
        text = (f"# The eq18-field model on synthetic non-stationary maps\n\n"
                f"From `{args.out.name}`, written {datetime.date.today()}: {len(records)} "
                f"cases, 256 x 256 points, fields on 4 x 4 tiles, tile check on 2 x 4 tiles "
                f"with 19 simulations (10 % outside for a model that describes the surface); "
                f"{minutes:.0f} CPU minutes.\n\n{recovery_table(records)}\n")
        with atomic_output(args.out.with_suffix(".md")) as partial:
            Path(partial).write_text(text)
        print(text)
        return 0
    done = {(r["kind"], r["index"], r["seed"]) for r in load_records(args.out)}
    todo = [(kind, i) for i in range(args.cases) for kind in (args.kinds or KINDS)
            if (kind, i, args.seed) not in done]
    print(f"{len(todo)} case(s) to run, {len(done)} recorded")
    record = appending_records(
        args.out, lambda r: f"covered {r['covered']} ({r['seconds']:.0f} s)", len(todo))
    run_cases(_run_case, [(f"{kind} {i}", (kind, i, args.seed), f"field-{kind}-{i}")
                          for kind, i in todo],
              workers=args.workers, scheduler=args.scheduler, on_result=record)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
