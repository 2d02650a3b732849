"""The spurious-points chapter's real-file study at full size
(``roughgp.experiments.spurious_points.real_file_study`` on the whole map of every file of
``REAL_FILES``, seed 0), the run the chapter states its verdicts from.

One record per file goes to ``benchmarks/results/spurious_points_full.jsonl`` (the chapter
reads it, :func:`~roughgp.experiments.spurious_points.recorded_studies`), and the Markdown
table ``benchmarks/results/spurious_points_full.md`` (date, command, seconds; per file: the
RMSE of the GP and of linear interpolation on the unflagged held-out points, the band's
coverage, the self-check's and the cross-validation's verdicts with their evidence, the share
flagged and the detector's rounds). Each file is one case on the project's engine
(:func:`roughgp.batch.engine.run_cases`: a local Dask cluster of ``--workers`` processes, one
BLAS thread each, or ``--scheduler ADDRESS``); each record is appended to
``spurious_points_full.partial.jsonl`` as its file ends, so an interrupted run resumes with the
files not done, and the recorded file is written, in the order of ``REAL_FILES``, when all
are. Not a test: run it by hand, about 10-15 minutes on the 2-core machine shared with other
jobs.

    python benchmarks/spurious_points_full.py --workers 2
"""

from __future__ import annotations

import argparse
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
from roughgp.experiments import spurious_points as sp

RESULTS = Path(__file__).resolve().parent / "results"


def _row(r) -> str:
    scale, unit = (1.0, "µm") if r["file"] == "sample-land.x3p" else (1000.0, "nm")
    a = r["rmse"]["with flagging"]
    cv, check = r["cv_difference"], r["check_difference"]
    s2 = scale * scale
    return (f"| `{r['file']}` | {r['shape'][0]} x {r['shape'][1]} | {scale * a['GP']:.4g} | "
            f"{scale * a['linear']:.4g} {unit} | {r['band_coverage']:.1%} | "
            f"{r['self_check_verdict']} ({s2 * check[0]:.3g} ± {s2 * check[1]:.2g}, "
            f"{r['check_discs']} discs) | {r['cv_verdict']} "
            f"({s2 * cv[0]:.3g} ± {s2 * cv[1]:.2g}, "
            f"{r['cv_discs']} discs) | {r['flagged']} ({r['flagged_share']:.2%}) | "
            f"{', '.join(map(str, r['history']))}{'' if r['converged'] else ' (cap)'} |")


def _case_record(name) -> dict:
    return sp.study_record(sp.real_file_study(name, crop=None, seed=0))


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    add_cluster_options(parser)
    args = parser.parse_args(argv)
    start, began = time.perf_counter(), datetime.datetime.now(datetime.timezone.utc)
    partial = sp.RECORDED.with_suffix(".partial.jsonl")
    done = {r["file"] for r in read_records(partial)}
    cases = [(name, (_case_record, name), f"spurious-{name}") for name in sp.REAL_FILES
             if name not in done]
    run_cases(on_one_thread, cases, workers=args.workers, scheduler=args.scheduler,
              on_result=appending_records(partial, lambda r: f"{r['flagged']} flagged",
                                          len(cases)))
    by_file = {r["file"]: r for r in read_records(partial)}
    missing = [name for name in sp.REAL_FILES if name not in by_file]
    if missing:
        print(f"not done: {', '.join(missing)} (run again to resume)", file=sys.stderr)
        return 1
    seconds = time.perf_counter() - start
    records = [by_file[name] for name in sp.REAL_FILES]
    write_records(sp.RECORDED, records)
    partial.unlink()
    lines = [
        f"# Spurious points on the whole real files ({began:%Y-%m-%d})", "",
        "Command: `python benchmarks/spurious_points_full.py` (the chapter "
        "`spurious_points` with `ROUGHGP_FULL=1` computes the same), seed 0, on the 2-core "
        f"machine shared with other jobs: {seconds:.0f} s wall, started {began:%H:%M} UTC.", "",
        "RMSE on the measured, unflagged points hidden in discs (2 %), with the flagged points "
        "left out of the fit and the interpolation. Verdicts: which method has the lower mean "
        "squared error by more than one standard error over the discs; in brackets the GP's "
        "MSE minus linear's (µm² or nm²) ± its standard error. Rounds: the points the "
        "detector flagged in any round so far, after each (they only grow; '(cap)': the "
        "8-round cap came before a round that flagged no new point).", "",
        "| file | shape | GP | linear | band | self-check | cross-validation | flagged | rounds |",
        "|---|---|---|---|---|---|---|---|---|",
        *(_row(r) for r in records), ""]
    (RESULTS / "spurious_points_full.md").write_text("\n".join(lines))
    print("\n".join(lines))
    return 0


if __name__ == "__main__":
    sys.exit(main())
