"""The ladder of models on every map (``roughgp.experiments.model_ladder``): every rung on
every map of ``data/``, each cropped to its central ``--size`` points (default 256, the full
size), 19 simulations per check, seed 0.

Each result is appended to ``benchmarks/results/model_ladder_full_<size>.jsonl`` as it comes
(a long run keeps what it did; a later run of other rungs adds to it), and the Markdown table
``benchmarks/results/model_ladder_full_<size>.md`` (date, command, seconds, the table files x
rungs, the best rung per file and the share reproduced) is written from all its records. Not a
test: run it by hand. On the 2-core machine shared with other jobs, 256 x 256 took about 9
minutes per map for the four eq 18 rungs; 128 x 128 about 2.

    OMP_NUM_THREADS=1 python benchmarks/model_ladder_full.py [--size 128] [--rungs eq18 ...]
    python benchmarks/model_ladder_full.py --size 128 --report   # the table from the records

A rung run again (e.g. after a change of the check) goes to a part file, ``--out PART``, and
``--merge PART ...`` puts its records in place of the recorded ones of the same file and rung:

    OMP_NUM_THREADS=1 python benchmarks/model_ladder_full.py --size 128 --rungs sm-iaaft \
        --out /tmp/sm.jsonl
    python benchmarks/model_ladder_full.py --size 128 --merge /tmp/sm.jsonl
"""

from __future__ import annotations

import argparse
import dataclasses
import datetime
import json
import sys
import time
from pathlib import Path

from roughgp.common.atomic import atomic_output
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


def merge(parts, size) -> None:
    """Put the records of ``parts`` in place of the recorded ones of the same file and rung."""
    path = _paths(size)[0]
    records = [json.loads(line) for line in path.read_text().splitlines() if line]
    where = {(r["file"], r["rung"]): i for i, r in enumerate(records)}
    replaced = 0
    for part in parts:
        for line in Path(part).read_text().splitlines():
            if not line:
                continue
            r = json.loads(line)
            key = (r["file"], r["rung"])
            if key in where:
                records[where[key]] = r
                replaced += 1
            else:
                where[key] = len(records)
                records.append(r)
    with atomic_output(path) as partial:
        partial.write_text("".join(json.dumps(r) + "\n" for r in records))
    print(f"{replaced} records replaced, {len(records)} in {path}")


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rungs", nargs="*", default=list(ml.RUNGS), choices=list(ml.RUNGS))
    parser.add_argument("--files", nargs="*", default=[e.name for e in REAL_MAPS])
    parser.add_argument("--size", type=int, default=ml.crop_size(full=True),
                        help="the side of each map's central crop, points")
    parser.add_argument("--report", action="store_true", help="only write the report")
    parser.add_argument("--out", help="a part file to append to instead of the records")
    parser.add_argument("--merge", nargs="+", metavar="PART",
                        help="put these part files' records in place of the recorded ones")
    args = parser.parse_args(argv)
    command = "python benchmarks/model_ladder_full.py " + " ".join(sys.argv[1:])
    if args.report:
        write_report(command, float("nan"), args.size)
        return
    if args.merge:
        merge(args.merge, args.size)
        return
    RESULTS.mkdir(exist_ok=True)
    start = time.perf_counter()

    def keep(result):
        with (Path(args.out) if args.out else _paths(args.size)[0]).open("a") as out:
            out.write(json.dumps(result.to_record()) + "\n")
        print(f"{result.file} {result.rung}: {result.n_outside} outside "
              f"{result.outside}, {result.fit_seconds:.0f} s fit", flush=True)

    ml.model_ladder(args.files, args.rungs, size=args.size, progress=keep)
    if not args.out:
        write_report(command, time.perf_counter() - start, args.size)


if __name__ == "__main__":
    main()
