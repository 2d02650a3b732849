"""Do the simulations with the measured heights (IAAFT) describe the half of a map they were
not fitted on? ``roughgp.experiments.iaaft_held_out`` on synthetic maps of known models (issue
40: the check of the IAAFT models).

Each case (a 128 x 256 map of eq 18, Gaussian or lognormal heights, or a map whose halves
differ: two regions, a roughness gradient; the measured-PSD model with Gaussian and with IAAFT
heights fitted on its left half and checked on both halves, plug-in and predictive) is
appended to ``benchmarks/results/iaaft_held_out.jsonl`` as it ends (a case already there is
skipped: a run resumes; a marginal added to the experiment later is run alone for the recorded
cases, a line of its own); ``--report`` writes the Markdown table beside it and prints it. The
cases run on the Dask engine of ``roughgp batch`` (one BLAS thread per worker). Not a test:

    python benchmarks/iaaft_held_out.py --cases 40 --workers 2
    python benchmarks/iaaft_held_out.py --cases 45 --kinds gaussian --marginals iaaft-tiles
    python benchmarks/iaaft_held_out.py --report
"""

from __future__ import annotations

import argparse
import datetime
import functools
from pathlib import Path

from roughgp.batch.engine import add_cluster_options, appending_records, on_one_thread, run_cases
from roughgp.common.atomic import atomic_output
from roughgp.experiments.iaaft_held_out import (KINDS, MARGINALS, MARGINALS_OF, RECORDED,
                                                iaaft_held_out_case, load_records,
                                                per_parameter, summary)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--cases", type=int, default=40, help="cases of each kind (default 40)")
    parser.add_argument("--seed", type=int, default=0)
    add_cluster_options(parser)
    parser.add_argument("--kinds", nargs="+", choices=KINDS, default=KINDS,
                        help="the kinds of map to run (default all)")
    parser.add_argument("--marginals", nargs="+", choices=MARGINALS, default=MARGINALS,
                        help="the marginals to run, where the kind runs them (default all)")
    parser.add_argument("--report", action="store_true", help="write and print the table")
    args = parser.parse_args(argv)
    if args.report:
        records = load_records()
        minutes = sum(r["seconds"] for r in records) / 60
        text = (f"# The IAAFT heights out of sample ({datetime.date.today()})\n\n"
                f"From `{RECORDED.name}`: {len(records)} cases, {minutes:.0f} CPU minutes. The "
                f"share of the 13 parameters outside 19 simulations, per case, averaged over "
                f"the cases (10 % for a check at its level):\n\n"
                f"{summary(records).to_markdown(index=False, floatfmt='.3f')}\n\n"
                f"Per parameter on the other half, where one stationary model describes the "
                f"map: the share of the cases with the parameter outside, its 95 % interval "
                f"and whether it lies within 10 % ± 3 % (yes / no / ? undecided: the interval "
                f"straddles a bound):\n\n"
                f"{per_parameter(records).to_markdown(index=False)}\n")
        with atomic_output(RECORDED.with_suffix(".md")) as partial:
            Path(partial).write_text(text)
        print(text)
        return 0
    done = {(r["kind"], r["index"], r["seed"]): set(r["checks"]) for r in load_records()}
    todo = [(kind, i, tuple(m for m in MARGINALS_OF[kind] if m in args.marginals
                            and m not in done.get((kind, i, args.seed), ())))
            for i in range(args.cases) for kind in args.kinds]
    todo = [t for t in todo if t[2]]
    print(f"{len(todo)} case(s) to run, {len(done)} recorded in {RECORDED}", flush=True)
    cases = [(f"{kind} {i} ({', '.join(marginals)})",
              (functools.partial(iaaft_held_out_case, marginals=marginals, seed=args.seed),
               kind, i),
              f"iaaft-{kind}-{i}-{args.seed}-{'-'.join(marginals)}")
             for kind, i, marginals in todo]
    run_cases(on_one_thread, cases, workers=args.workers, scheduler=args.scheduler,
              on_result=appending_records(
                  RECORDED, lambda r: " ".join(f"{m} {len(c['fitted'])}/{len(c['held_out'])}"
                                               for m, c in r["checks"].items())
                  + f" ({r['seconds']:.0f} s)", len(todo)))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
