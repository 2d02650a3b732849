"""The ladder of models on every map (``roughgp.experiments.model_ladder``): every rung on
every map of ``data/``, each cropped to its central ``--size`` points (default 256, the full
size), 19 simulations per check, seed 0.

Each (map, rung) is one case (``model_ladder.ladder_case``) on the project's engine
(:func:`roughgp.batch.engine.run_cases`: a local Dask cluster of ``--workers`` processes, one
BLAS thread each, or ``--scheduler ADDRESS``); its record is appended to
``benchmarks/results/model_ladder_full_<size>.jsonl`` as it ends, so a long run keeps what it
did and a rerun runs only the cases not recorded. The Markdown table
``benchmarks/results/model_ladder_full_<size>.md`` (date, command, seconds, the table files x
rungs, the best rung per file and the share reproduced) is written from all its records. Not a
test: run it by hand. On the 2-core machine shared with other jobs, 256 x 256 took about 9
minutes per map for the four eq 18 rungs; 128 x 128 about 2.

    python benchmarks/model_ladder_full.py --size 128 --workers 2 [--rungs eq18 ...]
    python benchmarks/model_ladder_full.py --size 128 --report   # the table from the records

A rung run again (e.g. after a change of the check): ``--rerun`` drops the recorded cases of
the rungs and files given and runs them again, in place:

    python benchmarks/model_ladder_full.py --size 128 --rungs sm-iaaft --rerun
"""

from __future__ import annotations

import argparse
import dataclasses
import datetime
import sys
import time
from pathlib import Path

from roughgp.batch.engine import (
    add_cluster_options,
    appending_records,
    on_one_thread,
    run_cases,
)
from roughgp.common.jsonl import read_records, write_records
from roughgp.experiments import model_ladder as ml
from roughgp.experiments.real_maps import REAL_MAPS

RESULTS = Path(__file__).resolve().parent / "results"


def _paths(size):
    return (RESULTS / f"model_ladder_full_{size}.jsonl", RESULTS / f"model_ladder_full_{size}.md")


def write_report(command, seconds, size) -> None:
    records_path, report = _paths(size)
    ladder = dataclasses.replace(ml.recorded_ladder(records_path, size), seconds=seconds)
    fit_seconds = sum(r.fit_seconds for r in ladder.results)
    check_seconds = sum(r.check_seconds for r in ladder.results)
    lines = [f"# The ladder of models on every map, {size} x {size} "
             f"({datetime.date.today().isoformat()})", "",
             f"Command: `{command}`"
             + (f"; {seconds:.0f} s of wall time" if seconds == seconds else "")
             + f" (the records, `{records_path.name}`, may come from several runs), on the "
             f"2-core machine shared with other jobs. Each map's central {ladder.size} x "
             f"{ladder.size} points (the whole of a shorter axis); 19 simulations per check; "
             f"seed 0. Fits and checks: {fit_seconds:.0f} s and {check_seconds:.0f} s in all "
             f"(the held-out scores not counted).", "",
             ml.markdown_table(ladder), "",
             f"Best model leaves <= {ml.MAX_OUTSIDE} of 13 outside on "
             f"{len(ladder.reproduced())} of {len(ladder.files)} maps "
             f"({100 * ladder.share_reproduced():.0f} %; target {100 * ml.TARGET_SHARE:.0f} %).",
             ""]
    lines += [f"- {line}" for line in ml.verdict_lines(ladder)]
    report.write_text("\n".join(lines) + "\n")
    print(report.read_text())


def _case_record(name, rung, size) -> dict:
    return ml.ladder_case(name, rung, size).to_record()


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rungs", nargs="*", default=list(ml.RUNGS), choices=list(ml.RUNGS))
    parser.add_argument("--files", nargs="*", default=[e.name for e in REAL_MAPS])
    parser.add_argument("--size", type=int, default=ml.crop_size(full=True),
                        help="the side of each map's central crop, points")
    parser.add_argument("--report", action="store_true", help="only write the report")
    parser.add_argument("--rerun", action="store_true",
                        help="drop the recorded cases of these rungs and files and run them again")
    add_cluster_options(parser)
    args = parser.parse_args(argv)
    command = "python benchmarks/model_ladder_full.py " + " ".join(sys.argv[1:])
    if args.report:
        write_report(command, float("nan"), args.size)
        return
    path = _paths(args.size)[0]
    wanted = {(f, g) for f in args.files for g in args.rungs}
    records = read_records(path)
    if args.rerun:
        kept = [r for r in records if (r["file"], r["rung"]) not in wanted]
        write_records(path, kept)
        print(f"{len(records) - len(kept)} recorded cases dropped to be run again")
        records = kept
    done = {(r["file"], r["rung"]) for r in records}
    cases = [((f, g), (_case_record, f, g, args.size), f"ladder-{f}-{g}")
             for f in args.files for g in args.rungs if (f, g) not in done]
    print(f"{len(cases)} cases to run ({len(wanted) - len(cases)} recorded)", flush=True)
    start = time.perf_counter()

    def describe(record):
        outside = record.get("outside")
        return (f"{len(outside)} outside {outside}" if outside is not None else
                f"no check: {record.get('description')}") + f", {record['fit_seconds']:.0f} s fit"

    run_cases(on_one_thread, cases, workers=args.workers, scheduler=args.scheduler,
              on_result=appending_records(path, describe, len(cases)))
    write_report(command, time.perf_counter() - start, args.size)


if __name__ == "__main__":
    main()
