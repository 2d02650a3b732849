"""Does ``roughgp batch`` give, file by file, the numbers of the single commands? (issue 42:
"a batch over every map of ``data/`` (texture, ``fit --model auto``, check) gives, file by file,
the same numbers as the single commands").

Every map of ``data/`` (the files that read as surfaces) goes once through ``roughgp batch
--steps texture,fit,check --model auto`` on a local Dask cluster, and once through the three
single commands, each a process of its own, with the seed the batch gave the file (from the
user's seed and the file's SHA-256): ``roughgp texture FILE --json``, ``roughgp fit ground FILE
--model auto --seed S``, ``roughgp check MODEL FILE --seed S --json``. The single commands of
different files run side by side on the same engine (:func:`roughgp.batch.engine.run_cases`).
Compared, digit for digit: every texture parameter; the rung chosen, its equation and every
hyperparameter of the model; each checked parameter's measured value, rank and verdict. It
prints one line per map and a summary, and writes them to ``--record`` when given. Not a test
(about 45 CPU minutes): run it by hand at the repository root,

    python benchmarks/batch_vs_single.py --workers 2 \
        --record benchmarks/results/batch_vs_single_2core_<date>.md
"""

from __future__ import annotations

import argparse
import datetime
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "benchmarks"))

os.environ.setdefault("OMP_NUM_THREADS", "1")

from batch_workers import maps  # noqa: E402  (the benchmarks folder, put on the path above)

ROUGHGP = [str(Path(sys.executable).with_name("roughgp"))]


def single_commands(path: str, seed: int, folder: str) -> dict:
    """``texture``, ``fit ground --model auto`` and ``check`` of ``path`` as a user runs them,
    each a process; their JSON outputs (or the error of the one that failed)."""
    stem = Path(folder) / Path(path).name
    texture, model, check = (f"{stem}.texture.json", f"{stem}.model.json",
                             f"{stem}.check.json")
    steps = (("texture", [path, "--json", texture]),
             ("fit", ["ground", path, "--model", "auto", "--seed", str(seed), "--out", model]),
             ("check", [model, path, "--seed", str(seed), "--json", check]))
    for command, args in steps:
        done = subprocess.run(ROUGHGP + [command, *args], capture_output=True, text=True,
                              check=False)
        if done.returncode != 0:
            return {"error": f"{command}: exit {done.returncode}: {done.stderr.strip()[-300:]}"}
    return {name: json.loads(Path(file).read_text())
            for name, file in (("texture", texture), ("model", model), ("check", check))}


def differences(record: dict, single: dict) -> list:
    """What differs between the batch's record of a file and its single commands' outputs."""
    if "error" in single:
        return [single["error"]]
    found = []
    if single["texture"]["parameters"] != record["texture"]["parameters"]:
        found.append("texture")
    model, fit = single["model"], record["fit"]
    if model["equation"] != fit["equation"]:
        found.append(f"equation {model['equation']} / {fit['equation']}")
    if model["hyperparameters"] != fit["hyperparameters"]:
        found.append("hyperparameters")
    checked = {p["name"]: (p["measured"], p["rank"], p["outside"])
               for p in single["check"]["parameters"]}
    batch = {name: (p["measured"], p["rank"], p["outside"])
             for name, p in record["check"]["parameters"].items()}
    if checked != batch:
        found.append("check: " + ", ".join(sorted(n for n in checked
                                                   if checked[n] != batch.get(n))))
    return found


def main(argv=None) -> int:
    from roughgp.batch.engine import add_cluster_options, run_cases
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--data", type=Path, default=ROOT / "data")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--record", type=Path, help="also write the report here (Markdown)")
    add_cluster_options(parser)
    args = parser.parse_args(argv)
    files = [str(p) for p in maps(args.data)]
    lines = []
    with tempfile.TemporaryDirectory(prefix="batch-vs-single-") as tmp:
        out = Path(tmp) / "batch"
        start = time.perf_counter()
        batch = subprocess.run(ROUGHGP + ["batch", *files, "--out", str(out), "--steps",
                                          "texture,fit,check", "--model", "auto", "--seed",
                                          str(args.seed)]
                               + (["--workers", str(args.workers)] if args.workers else [])
                               + (["--scheduler", args.scheduler] if args.scheduler else []),
                               capture_output=True, text=True, check=False)
        batch_seconds = time.perf_counter() - start
        records = {r["path"]: r for r in (json.loads(p.read_text())
                                          for p in (out / "records").glob("*.json"))}
        singles = {}
        start = time.perf_counter()
        run_cases(single_commands,
                  [(r["path"], (r["path"], r["seed"], tmp), f"single-{i}")
                   for i, r in enumerate(records.values()) if r.get("status") == "done"],
                  workers=args.workers, scheduler=args.scheduler,
                  on_result=lambda key, result: singles.__setitem__(
                      key, result if isinstance(result, dict) else {"error": repr(result)}))
        single_seconds = time.perf_counter() - start
    same = 0
    for path in files:
        record = records.get(path)
        name = Path(path).name
        if record is None or record.get("status") != "done":
            lines.append(f"- {name}: the batch failed: "
                         f"{(record or {}).get('error', 'no record')}")
            continue
        found = differences(record, singles.get(path, {"error": "not run"}))
        same += not found
        lines.append(f"- {name}: {record['fit'].get('chosen', record['fit']['equation'])}, "
                     f"{sum(p['outside'] for p in record['check']['parameters'].values())} "
                     f"outside: " + ("the same numbers" if not found else
                                     "DIFFERENT: " + "; ".join(found)))
    head = [f"# `roughgp batch` against the single commands ({datetime.date.today()})", "",
            f"`python benchmarks/batch_vs_single.py --workers {args.workers}`: {len(files)} "
            f"maps of `{args.data.name}/`, texture, `fit ground --model auto` and `check` "
            f"(seed {args.seed}); the batch (exit {batch.returncode}) {batch_seconds:.0f} s, "
            f"the single commands {single_seconds:.0f} s; load average "
            f"{os.getloadavg()[0]:.2f} at the end.", "",
            f"The same numbers, digit for digit, on {same} of {len(files)} maps.", ""]
    text = "\n".join(head + lines) + "\n"
    print(text)
    if args.record:
        args.record.write_text(text, encoding="utf-8")
    return 0 if same == len(files) else 1


if __name__ == "__main__":
    raise SystemExit(main())
