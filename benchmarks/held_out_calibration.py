"""Is the out-of-sample check calibrated, and do the predictive simulations help?
``roughgp.experiments.held_out.held_out_case`` on synthetic maps of known models (issue 40,
item 1: at least 200 cases; about 10 % outside per parameter for a model that describes the
surface).

Each case (a map of one of ``KINDS``, 64 x 128 by default, eq 18 fitted on its left half,
checked on both halves, plug-in and predictive, and the tile check) is appended to
``benchmarks/results/held_out_calibration.jsonl`` (other shapes:
``held_out_calibration_<ny>x<nx>.jsonl``) as it comes (a case already there is skipped: a run
can be resumed); ``--report`` writes the Markdown table beside it (``.md``) and prints it. The
cases run on the Dask engine of ``roughgp batch`` (:func:`roughgp.batch.engine.run_cases`, one
BLAS thread per worker; ``--workers`` or ``--scheduler``). ``--sandwich`` (with ``--likelihood
whittle``) adds the predictive check whose parameters are drawn from the Whittle fit's sandwich
covariance (no refits: cheap at 256 x 256). Not a test: run it by hand,

    python benchmarks/held_out_calibration.py --cases 50 --workers 2   # 50 of each kind
    python benchmarks/held_out_calibration.py --shape 256 512 --likelihood whittle --sandwich \
        --models 0 --kinds stationary holes --cases 100 --workers 2
    python benchmarks/held_out_calibration.py --report
    python benchmarks/held_out_calibration.py --shape 256 512 --report
"""

from __future__ import annotations

import argparse
import datetime
from pathlib import Path

from roughgp.batch.engine import add_cluster_options, appending_records, on_one_thread, run_cases
from roughgp.common.atomic import atomic_output
from roughgp.experiments.held_out import (KINDS, SHAPE, calibration_table, held_out_case,
                                          load_records, recorded_path, shares_table)


def _case(kind, index, shape, n_models, seed, likelihood, sandwich):
    return held_out_case(kind, index, shape=shape, n_models=n_models, seed=seed,
                         likelihood=likelihood, sandwich=sandwich)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--cases", type=int, default=50, help="cases of each kind (default 50)")
    parser.add_argument("--kinds", nargs="+", default=None, help="kinds (default: all)")
    parser.add_argument("--models", type=int, default=9,
                        help="bootstrap refits of the predictive check (default 9)")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--likelihood", choices=("blocks", "whittle"), default="blocks",
                        help="the fit's likelihood (default blocks)")
    parser.add_argument("--shape", type=int, nargs=2, default=list(SHAPE), metavar=("NY", "NX"),
                        help=f"the maps' points (default {SHAPE[0]} {SHAPE[1]}; the halves are "
                             "NY x NX/2)")
    parser.add_argument("--sandwich", action="store_true",
                        help="add the predictive check drawn from the Whittle fit's sandwich "
                             "covariance (needs --likelihood whittle)")
    add_cluster_options(parser)
    parser.add_argument("--out", type=Path, default=None,
                        help="the JSONL file (default: by --shape, in benchmarks/results)")
    parser.add_argument("--report", action="store_true", help="write and print the table")
    args = parser.parse_args(argv)
    if args.sandwich and args.likelihood != "whittle":
        parser.error("--sandwich needs --likelihood whittle")
    if min(args.shape) < 32 or args.shape[1] % 2:
        parser.error(f"--shape: NY and NX >= 32 and NX even, got {args.shape}")
    args.out = args.out or recorded_path(args.shape)
    if args.report:
        records = load_records(args.out)
        sections = []
        for likelihood in ("blocks", "whittle"):
            rows = [r for r in records if r.get("likelihood", "blocks") == likelihood]
            if not rows:
                continue
            models = max(r["n_models"] for r in rows)
            ny, nx = rows[0]["shape"]
            sections.append(
                f"## eq 18 fitted by the {likelihood} likelihood\n\n{len(rows)} cases ({ny} x {nx} "
                f"maps, eq 18 fitted on the left half, 19 simulations, {models} bootstrap "
                f"refits for the predictive checks; {sum(r['seconds'] for r in rows) / 60:.0f} "
                f"CPU minutes). Share of the cases with the parameter outside the simulated "
                f"range (10 % for a check at its level):\n\n"
                f"{shares_table(records, likelihood=likelihood)}\n\n"
                f"Where the model's family describes the surface (the stationary maps and those "
                f"with holes together): the share outside per parameter with its 95 % interval, "
                f"and whether it lies within 10 % +- 3 % (yes / no / undecided: the interval "
                f"straddles a bound):\n\n{calibration_table(records, likelihood=likelihood)}\n"
                + "".join(f"\nNo sandwich draws for {r['kind']} {r['index']}: "
                          f"{r['sandwich_refused']}\n"
                          for r in rows if r.get("sandwich_refused")))
        text = (f"# The out-of-sample check on synthetic maps of known models\n\n"
                f"From `{args.out.name}`, written {datetime.date.today()}.\n\n"
                + "\n".join(sections))
        with atomic_output(args.out.with_suffix(".md")) as partial:
            Path(partial).write_text(text)
        print(text)
        return 0
    shape = tuple(args.shape)
    done = {(r["kind"], r["index"], r["seed"], r.get("likelihood", "blocks"))
            for r in load_records(args.out) if tuple(r["shape"]) == shape}
    todo = [(kind, i) for i in range(args.cases) for kind in (args.kinds or KINDS)
            if (kind, i, args.seed, args.likelihood) not in done]
    print(f"{len(todo)} case(s) to run, {len(done)} recorded in {args.out}", flush=True)
    cases = [(f"{kind} {i}", (_case, kind, i, shape, args.models, args.seed, args.likelihood,
                              args.sandwich), f"held-out-{kind}-{i}-{args.seed}")
             for kind, i in todo]
    run_cases(on_one_thread, cases, workers=args.workers, scheduler=args.scheduler,
              on_result=appending_records(
                  args.out, lambda r: f"held-out {r['outside']['held-out']} "
                                      f"({r['seconds']:.0f} s)", len(todo)))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
