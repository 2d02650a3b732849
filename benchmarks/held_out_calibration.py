"""Is the out-of-sample check calibrated, and do the predictive simulations help?
``roughgp.experiments.held_out.held_out_case`` on synthetic maps of known models (issue 40,
item 1: at least 200 cases; about 10 % outside per parameter for a model that describes the
surface).

Each case (a 64 x 128 map of one of ``KINDS``, eq 18 fitted on its left half, checked on both
halves, plug-in and predictive, and the tile check) is appended to
``benchmarks/results/held_out_calibration.jsonl`` as it comes (a case already there is
skipped: a run can be resumed); ``--report`` writes the Markdown table
``benchmarks/results/held_out_calibration.md`` and prints it. The cases run on a
``dask.distributed`` local cluster, one BLAS thread per worker. Not a test: run it by hand,

    python benchmarks/held_out_calibration.py --cases 50 --workers 2   # 50 of each kind
    python benchmarks/held_out_calibration.py --report
"""

from __future__ import annotations

import argparse
import datetime
import json
from pathlib import Path

from roughgp.common.atomic import atomic_output
from roughgp.experiments.held_out import KINDS, RECORDED, load_records, shares_table



def _run_case(kind, index, n_models, seed, likelihood):
    from threadpoolctl import threadpool_limits

    from roughgp.experiments.held_out import held_out_case
    with threadpool_limits(1):
        return held_out_case(kind, index, n_models=n_models, seed=seed, likelihood=likelihood)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--cases", type=int, default=50, help="cases of each kind (default 50)")
    parser.add_argument("--kinds", nargs="+", default=None, help="kinds (default: all)")
    parser.add_argument("--models", type=int, default=9,
                        help="bootstrap refits of the predictive check (default 9)")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--likelihood", choices=("blocks", "whittle"), default="blocks",
                        help="the fit's likelihood (default blocks)")
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--out", type=Path, default=RECORDED)
    parser.add_argument("--report", action="store_true", help="write and print the table")
    args = parser.parse_args(argv)
    if args.report:
        records = load_records(args.out)
        sections = []
        for likelihood in ("blocks", "whittle"):
            rows = [r for r in records if r.get("likelihood", "blocks") == likelihood]
            if not rows:
                continue
            models = max(r["n_models"] for r in rows)
            sections.append(
                f"## eq 18 fitted by the {likelihood} likelihood\n\n{len(rows)} cases (64 x 128 "
                f"maps, eq 18 fitted on the left half, 19 simulations, {models} bootstrap "
                f"refits for the predictive checks; {sum(r['seconds'] for r in rows) / 60:.0f} "
                f"CPU minutes). Share of the cases with the parameter outside the simulated "
                f"range (10 % for a check at its level):\n\n"
                f"{shares_table(records, likelihood=likelihood)}\n")
        text = (f"# The out-of-sample check on synthetic maps of known models\n\n"
                f"From `{args.out.name}`, written {datetime.date.today()}.\n\n"
                + "\n".join(sections))
        with atomic_output(args.out.with_suffix(".md")) as partial:
            Path(partial).write_text(text)
        print(text)
        return 0
    done = {(r["kind"], r["index"], r["seed"], r.get("likelihood", "blocks"))
            for r in load_records(args.out)}
    todo = [(kind, i) for i in range(args.cases) for kind in (args.kinds or KINDS)
            if (kind, i, args.seed, args.likelihood) not in done]
    print(f"{len(todo)} case(s) to run, {len(done)} recorded")
    from dask.distributed import Client, LocalCluster, as_completed
    with LocalCluster(n_workers=args.workers, threads_per_worker=1, processes=True,
                      dashboard_address=None) as cluster, Client(cluster) as client:
        futures = [client.submit(_run_case, kind, i, args.models, args.seed, args.likelihood,
                                 pure=False)
                   for kind, i in todo]
        args.out.parent.mkdir(parents=True, exist_ok=True)
        for n, future in enumerate(as_completed(futures), 1):
            record = future.result()
            with open(args.out, "a") as handle:
                handle.write(json.dumps(record) + "\n")
            print(f"[{n}/{len(todo)}] {record['kind']} {record['index']}: "
                  f"held-out {record['outside']['held-out']} ({record['seconds']:.0f} s)",
                  flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
