"""The fill's 95 % band in holes of 2 to 40 points across, on every map of ``data/`` (issue 44:
"the band covers 93-97 % of held-out true heights per hole-size class").

Each case (:func:`roughgp.experiments.hole_coverage.coverage_case`) holes a map's central 256²
points in discs of four size classes, fills it as ``roughgp fill --band`` does and counts the
true heights inside the band per class. Each case is appended to
``benchmarks/results/hole_coverage.jsonl`` as it ends (a case already there is skipped: a run
can be resumed); ``--report`` writes ``benchmarks/results/hole_coverage.md`` and prints it. The
cases run on the project's engine (:func:`roughgp.batch.engine.run_cases`: a local Dask
cluster, one BLAS thread per worker, or ``--scheduler ADDRESS``). Not a test: run it by hand,

    python benchmarks/hole_coverage.py --seeds 10 --workers 2   # about 15 minutes on 2 cores
    python benchmarks/hole_coverage.py --report
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
from roughgp.experiments.hole_coverage import (
    CROP,
    HOLE_CLASSES,
    RECORDED,
    TARGET,
    coverage_case,
    coverage_table,
    load_records,
)
from roughgp.experiments.real_maps import REAL_MAPS


def report(records) -> str:
    """The Markdown report of the recorded cases."""
    table = coverage_table(records)
    minutes = sum(r["seconds"] for r in records) / 60
    on = sum(row["on_target"] for row in table)
    consistent = sum(row["consistent"] for row in table)
    clear = ", ".join(f"{row['map']} {row['across'][0]}-{row['across'][1]}" for row in table
                      if row["clearly_below"] or row["clearly_above"])
    lines = [f"# The fill's band in holes of every size ({datetime.date.today()})", "",
             f"From `{RECORDED.name}`: {len(records)} cases (maps of `data/`, central {CROP}² "
             f"points; per case {', '.join(f'{n} holes {lo}-{hi}' for lo, hi, n in HOLE_CLASSES)}"
             f" points across), {minutes:.0f} CPU minutes of fills. Coverage of the 95 % band "
             f"by hole size and depth; in brackets the self-check's one factor it replaced. "
             f"Within {TARGET[0]:.0%}-{TARGET[1]:.0%}: {on} of {len(table)} map-class pairs. "
             f"The holes of a case err together: after each share, its standard error with "
             f"the cases as clusters. Within 2 standard errors of 95 %: {consistent} of "
             f"{len(table)}; outside the target by more than 2 standard errors: "
             f"{clear or 'none'}.",
             "", "| map | seeds | " + " | ".join(f"{lo}-{hi} across" for lo, hi, _ in
                                                  HOLE_CLASSES) + " |",
             "|---|---|" + "---|" * len(HOLE_CLASSES)]
    by_map = {}
    for row in table:
        by_map.setdefault(row["map"], {})[row["across"]] = row
    for name, rows in by_map.items():
        cells = []
        for lo, hi, _ in HOLE_CLASSES:
            row = rows.get((lo, hi))
            cells.append("-" if row is None else
                         f"{row['coverage']:.1%} ± {row['standard_error']:.1%} "
                         f"({row['coverage_one_factor']:.1%})"
                         + ("" if row["on_target"] else " *")
                         + (" †" if row["clearly_below"] or row["clearly_above"] else ""))
        lines.append(f"| {name} | {max(r['cases'] for r in rows.values())} | "
                     + " | ".join(cells) + " |")
    lines += ["", "`*`: outside the target; `†`: outside it by more than 2 standard errors."]
    return "\n".join(lines) + "\n"


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--seeds", type=int, default=10, help="cases per map (default 10)")
    parser.add_argument("--maps", nargs="+", default=None, help="maps of data/ (default: all)")
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
    names = args.maps or [e.name for e in REAL_MAPS]
    done = {(r["map"], r["seed"]) for r in load_records(args.out)}
    todo = [(name, seed) for seed in range(args.seeds) for name in names
            if (name, seed) not in done]
    print(f"{len(todo)} case(s) to run, {len(done)} recorded", flush=True)
    record = appending_records(args.out, lambda r: ", ".join(
        f"{c['inside'] / max(c['points'], 1):.2f}" for c in r["classes"])
        + f" ({r['seconds']:.0f} s)", len(todo))
    run_cases(on_one_thread, [(f"{name} {seed}", (coverage_case, name, seed),
                               f"holes-{name}-{seed}")
                          for name, seed in todo],
              workers=args.workers, scheduler=args.scheduler, on_result=record)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
