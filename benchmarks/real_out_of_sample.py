"""The real maps of ``data/`` out of sample: each model fitted on one half of a map's central
window and checked on both halves (``roughgp.experiments.real_out_of_sample``; issue 40).

For each model of ``MODELS`` and each half (``left`` for wide windows, ``top`` for tall ones),
one ``roughgp batch WINDOWS --part HALF --steps fit,check`` run, as a user would type it, on
the project's engine (a local Dask cluster of ``--workers`` processes, or ``--scheduler``).
The windows are written once to ``--work`` (default ``.real_out_of_sample/``, not committed)
and each batch's folder is kept there, so an interrupted run resumes where it stopped. The
rows (map, model, the parameters outside on each half, the rung, seconds, error) are written to
``benchmarks/results/real_out_of_sample.jsonl`` and the report to ``real_out_of_sample.md``.
Not a test: run it by hand,

    python benchmarks/real_out_of_sample.py --workers 2     # about an hour on 2 cores
    python benchmarks/real_out_of_sample.py --report        # the report of the recorded rows

A model's run stopped part-way (Ctrl-C) resumes with the same command; ``--collect`` records
what the batches in ``--work`` hold without running more (the report counts each model over
the maps it was run on).
"""

from __future__ import annotations

import argparse
import datetime
import json
import subprocess
import sys
from pathlib import Path

from roughgp.batch.engine import add_cluster_options
from roughgp.common.atomic import atomic_output
from roughgp.common.jsonl import write_records
from roughgp.experiments.real_out_of_sample import (
    LONG,
    MODELS,
    PASS,
    RECORDED,
    SHORT,
    load_rows,
    per_map,
    row_of,
    summary,
    write_windows,
)


def run(work: Path, workers, scheduler, models, collect=False) -> list:
    """Run every model's batches (``collect``: only read the records already there) and
    return the rows of their records."""
    groups = write_windows(work / "windows")
    roughgp = str(Path(sys.executable).with_name("roughgp"))
    cluster = (["--scheduler", scheduler] if scheduler else
               ["--workers", str(workers)] if workers else [])   # batch's default: the cores
    rows = []
    for model in models:
        for part, paths in groups.items():
            out = work / f"{model.name}-{part}"
            command = [roughgp, "batch", *map(str, paths), "--part", part, "--steps",
                       "fit,check", *model.options, *cluster, "--out", str(out)]
            if not collect:
                print("$", " ".join(command[1:]), flush=True)
                done = subprocess.run(command)
                if done.returncode in (2, 130):
                    raise SystemExit(done.returncode)
            for record in sorted((out / "records").glob("*.json")):
                rows.append(row_of(model.name, json.loads(record.read_text())))
    return rows


def report(rows) -> str:
    """The Markdown report of the recorded rows."""
    hours = sum(r["seconds"] or 0 for r in rows) / 3600
    lines = [f"# The real maps out of sample ({datetime.date.today()})", "",
             f"From `{RECORDED.name}`: {len(rows)} rows, {hours:.1f} CPU hours. Each map's "
             f"central window (at most {LONG} points along its longer axis, {SHORT} across) is "
             f"halved along its longer axis; each model is fitted on half A and checked with 19 "
             f"simulations on A and on B, which it did not see (`roughgp batch --part A --steps "
             f"fit,check`). Per model: the share of the maps with at most {PASS} of 13 "
             f"parameters outside on each half.", "",
             summary(rows).to_markdown(index=False, floatfmt=".2f"), "",
             "Per map, outside on A / outside on B:", "",
             per_map(rows).to_markdown(), ""]
    errors = [f"- {r['map']}, {r['model']}: {r['error']}" for r in rows if r["error"]]
    if errors:
        lines += ["Refused:", "", *errors, ""]
    return "\n".join(lines)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--work", default=".real_out_of_sample",
                        help="the folder of the windows and the batches (resumed if present)")
    add_cluster_options(parser)
    parser.add_argument("--models", help="comma-separated names of MODELS (default all)")
    parser.add_argument("--report", action="store_true",
                        help="only write and print the report of the recorded rows")
    parser.add_argument("--collect", action="store_true",
                        help="record the rows of the batches already in --work without running "
                             "them (a model stopped part-way: the maps it finished)")
    args = parser.parse_args(argv)
    if not args.report:
        names = args.models.split(",") if args.models else [m.name for m in MODELS]
        unknown = set(names) - {m.name for m in MODELS}
        if unknown:
            parser.error(f"--models: unknown {sorted(unknown)}; choose from "
                         f"{[m.name for m in MODELS]}")
        rows = run(Path(args.work), args.workers, args.scheduler,
                   [m for m in MODELS if m.name in names], collect=args.collect)
        kept = [r for r in load_rows() if r["model"] not in names]
        write_records(RECORDED, kept + rows)
    text = report(load_rows())
    with atomic_output(RECORDED.with_suffix(".md")) as partial:
        Path(partial).write_text(text)
    print(text)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
