"""``roughgp batch FILES... --out FOLDER``: the steps of the single commands (texture, fit, check,
fill, simulate --from) over many files on a Dask cluster, one table out
(:func:`roughgp.batch.engine.run_batch`). Argument handling and messages only.
"""

from __future__ import annotations

import argparse
import os
from pathlib import Path

from roughgp.cli.bounds import bounds_text, integer
from roughgp.cli.options import PREDICTIVE_SOURCES, Given, cutoff
from roughgp.cli.output import UsageError, err
from roughgp.surface_models.schema import MAX_ANCHORS

__all__ = ["add_parser", "run", "steps_option", "exit_code", "FAILED_BASE"]

#: the exit code of a batch in which N files failed is FAILED_BASE + min(N, 99)
FAILED_BASE = 10

_STEPS = ("texture", "fit", "check", "fill", "simulate")
_HALVES = ("left", "right", "top", "bottom")   # roughgp.checking.held_out.HALVES
_ONE, _MANY = FAILED_BASE + 1, FAILED_BASE + 99

_BATCH = f"""\
Run the steps of the single commands over many measurement files on a Dask cluster and
collect one table: one row per file (path, SHA-256, reader, shape, spacing, unit, every ISO
parameter, the model's rung and hyperparameters, the check's rank and verdict per parameter,
the timings, the error if any), written as FOLDER/table.csv and, where pyarrow is installed,
FOLDER/table.parquet. Each file's artefacts go to FOLDER/files/NAME/ (model.json, filled.x3p,
simulated.x3p, check.png) and its record to FOLDER/records/NAME.json.

The steps (--steps, in this order whatever the order given): texture ('roughgp texture'),
fit ('roughgp fit ground' or, for a profile, 'fit profile'; --model, --marginal), check
('roughgp check' of the fitted model), fill ('roughgp fill', surfaces with unmeasured points)
and simulate ('roughgp simulate --from' the model at the file's shape). Each step calls the
library as its command does, so a file gives the numbers of its single commands run with
--seed set to the file's seed: the seed of each file is derived from --seed and the file's
SHA-256 (column seed), never from the order the files run in, so the table is the same
number for number with 1 worker or 20.

The engine is Dask (dask.distributed): by default a local cluster of --workers processes,
one thread each, the BLAS libraries on one thread in each; --scheduler ADDRESS runs on an
existing cluster (started with 'dask scheduler' and 'dask worker ADDRESS' on machines that
see the same files and FOLDER). Each file's record is written whole when the file ends; run
the same command again after an interruption (Ctrl-C) or a failure: files whose record is
complete and current (the same file bytes, the same options, the same roughgp version) are
skipped, failed files are tried again. A file that fails (unreadable, corrupt, a step
refused) gets its error in its row and the batch goes on.

Out of sample: --part left (right, top, bottom) fits each surface on that half; the check then
checks the model on the half it was fitted on and on the other half, which it did not see
(columns check.* and held_out.*, as 'roughgp check --held-out'): a model that describes the
surface, not the crop it saw, leaves about as few outside on the held-out half as on the
fitted one.

A folder is read without its subfolders, hidden files, and files that are no measurements
(.md, .json, .png, ..., LICENSE*, README*); files inside FOLDER are never inputs and an input
is never written over.

exit codes: 0 every file done; 2 a usage error (nothing was run); {FAILED_BASE} + N when N files
failed ({_ONE}: one file, ..., {_MANY}: 99 or more; their errors are in the table's error
column); 130 interrupted (the complete records are kept: run again to resume).

examples:
  roughgp batch data/ --out batch/                      texture, fit, check of every map
  roughgp batch 'maps/*.x3p' --steps texture,fit --model auto --workers 2 --out maps-batch/
  roughgp batch maps/ --part left --steps fit,check --out held-out/   out of sample
  roughgp batch maps/ --spurious --part left --steps fit,check --out clean/  spikes left out
  roughgp batch maps/ --scheduler tcp://HOST:8786 --out /shared/batch/"""


def steps_option(text: str) -> tuple:
    """``--steps``: a comma-separated list of steps, each one of :data:`_STEPS`."""
    steps = tuple(s.strip() for s in text.split(",") if s.strip())
    unknown = [s for s in steps if s not in _STEPS]
    if unknown or not steps:
        what = f"unknown step {unknown[0]!r}" if unknown else "no step given"
        raise argparse.ArgumentTypeError(f"{what}; the steps are {', '.join(_STEPS)} "
                                         f"(comma-separated)")
    return steps


def exit_code(failed: int) -> int:
    """0 when no file failed, else :data:`FAILED_BASE` + ``failed`` (at most 99)."""
    return 0 if failed == 0 else FAILED_BASE + min(failed, 99)


def add_parser(sub, formatter) -> None:
    """Add ``batch`` to the sub-command parsers ``sub``."""
    b = sub.add_parser("batch", formatter_class=formatter, description=_BATCH,
                       help="texture, fit, check, fill, simulate over many files (Dask): one "
                            "table")
    b.add_argument("files", nargs="+", metavar="FILES",
                   help="measurement files, globs (quoted: 'maps/*.x3p', '**' recursive) or "
                        "folders")
    b.add_argument("--out", required=True, metavar="FOLDER",
                   help="the output folder: table.csv, table.parquet, records/, files/ "
                        "(made if missing; an existing one is resumed)")
    b.add_argument("--steps", type=steps_option, default=("texture", "fit", "check"),
                   metavar="S,S",
                   help=f"the steps, comma-separated, of {', '.join(_STEPS)} (default "
                        f"texture,fit,check; check and simulate need fit)")
    b.add_argument("--seed", type=integer("--seed"), default=0, metavar="S",
                   help=f"the batch's seed, {bounds_text('--seed')} (default 0); each file's "
                        f"is derived from it and the file's SHA-256")
    b.add_argument("--workers", type=integer("--workers"), metavar="N",
                   help=f"local worker processes, {bounds_text('--workers')} (default: the "
                        f"cores, {_cores()} here)")
    b.add_argument("--scheduler", metavar="ADDRESS",
                   help="the address of an existing Dask scheduler (tcp://HOST:8786) instead "
                        "of a local cluster")
    g = b.add_argument_group("reading (as the single commands)")
    g.add_argument("--spacing", type=float, metavar="D",
                   help=f"the grid spacing in um, {bounds_text('--spacing')}, overriding "
                        f"each file's")
    g.add_argument("--kind", choices=("auto", "profile", "surface"), default="auto",
                   help="read text tables as profiles or surfaces (default auto)")
    g.add_argument("--channel", type=integer("--channel"), default=0, metavar="K",
                   help=f"the data channel of instrument files, {bounds_text('--channel')} "
                        f"(default 0)")
    g.add_argument("--unit", choices=("m", "mm", "um", "nm"), metavar="U",
                   help="the unit of the files' numbers (as the single commands' --unit)")
    g.add_argument("--spurious", action="store_true",
                   help="find each surface's spurious measured points (spikes, pits) once, on "
                        "the whole map, by the GP's leave-one-out scores (as the single "
                        "commands' --spurious, with the file's seed and --form), and treat "
                        "them as unmeasured in every step; columns spurious.* (default: no "
                        "point is removed)")
    o = b.add_argument_group("operators (texture and fit, as their commands)")
    o.add_argument("--form", choices=("plane", "polynomial", "cylinder", "none"),
                   default="plane", help="F-operator (default plane)")
    o.add_argument("--degree", type=integer("--degree"), default=2, metavar="N",
                   help=f"degree of --form polynomial, {bounds_text('--degree')} (default 2)")
    o.add_argument("--axis", choices=("auto", "x", "y"), default="auto",
                   help="the axis of --form cylinder (default auto)")
    o.add_argument("--s-filter", type=cutoff, metavar="S", action=Given,
                   help=f"S-filter nesting index in um ({bounds_text('--s-filter')}), auto or "
                        f"none (default: each step's own: texture auto, fit none)")
    o.add_argument("--l-filter", type=cutoff, metavar="L", action=Given,
                   help=f"L-filter nesting index in um ({bounds_text('--l-filter')}), auto or "
                        f"none (default: each step's own: auto; fit of a profile none)")
    lk = o.add_mutually_exclusive_group()
    lk.add_argument("--robust", dest="l_kind", action="store_const", const="robust",
                    default="gaussian", help="texture: the robust Gaussian L-filter")
    lk.add_argument("--stratified", dest="l_kind", action="store_const", const="stratified",
                    help="texture: ISO 13565-1's L-filter for stratified surfaces")
    o.add_argument("--unfiltered", action="store_true",
                   help="texture: no operator (the heights as read)")
    f = b.add_argument_group("fit (as roughgp fit ground / profile)")
    f.add_argument("--model", dest="rung",
                   choices=("eq18", "matern", "sm", "psd", "field", "population", "auto"),
                   default="eq18", help="the rung of a surface's model (default eq18; auto: "
                   "chosen by held-out kriging; field and population: eq 18 over the map's "
                   "--anchors tiles); profiles get eq 21")
    f.add_argument("--anchors", type=integer("--anchors"), nargs=2, default=None,
                   metavar=("M", "N"),
                   help=f"--model field or population: the M x N tiles of each map, M and N "
                        f"in [1, {MAX_ANCHORS}] (default 4 4 for field, 2 2 for population)")
    f.add_argument("--marginal", choices=("gaussian", "johnson", "iaaft"), default=None,
                   help="the heights' distribution (default gaussian; --model auto: chosen "
                        "by the out-of-sample check)")
    f.add_argument("--nu", type=float, choices=(0.5, 1.5, 2.5), default=0.5,
                   help="smoothness of eq 18 (default 0.5)")
    f.add_argument("--likelihood", choices=("blocks", "whittle"), default="blocks",
                   help="eq 18's likelihood (default blocks)")
    f.add_argument("--block", type=integer("--block"), default=24, metavar="B",
                   help=f"side of the fit's blocks in points, {bounds_text('--block')} "
                        f"(default 24)")
    f.add_argument("--blocks", type=integer("--blocks"), default=12, metavar="K",
                   help=f"blocks used by the fit, {bounds_text('--blocks')} (default 12)")
    f.add_argument("--mixtures", type=integer("--mixtures"), default=5, metavar="Q",
                   help=f"a profile's spectral-mixture components, "
                        f"{bounds_text('--mixtures')} (default 5)")
    f.add_argument("--candidates", type=integer("--candidates"), default=10, metavar="N",
                   help=f"a profile fit's initialisations, {bounds_text('--candidates')} "
                        f"(default 10)")
    f.add_argument("--part", choices=_HALVES, default=None,
                   help="fit each surface on this half only (top: the first rows); the check "
                        "then checks the model on that half and on the other half it did not "
                        "see (as 'roughgp fit ground --part' and 'check --held-out'); "
                        "profiles are fitted whole")
    c = b.add_argument_group("check, simulate and fill")
    c.add_argument("--simulations", type=integer("--simulations"), default=19, metavar="N",
                   help=f"check: simulations of the model, {bounds_text('--simulations')} "
                        f"(default 19)")
    c.add_argument("--predictive", type=integer("--predictive"), metavar="B",
                   help=f"check: draw the simulations from B models that carry the fit's "
                        f"uncertainty, {bounds_text('--predictive')} (default: the plug-in "
                        f"model); simulate: draw the surface's model first, the same way")
    c.add_argument("--predictive-from", choices=PREDICTIVE_SOURCES,
                   default="refits",
                   help="check and simulate: the models of --predictive: bootstrap refits, "
                        "eq 18 parameter sets of the Whittle sandwich covariance, or the "
                        "fitted part's tiles drawn with replacement (with --part) (as "
                        "'roughgp check' and 'roughgp simulate --from')")
    c.add_argument("--plots", action="store_true",
                   help="check: also write each file's figure (files/NAME/check.png)")
    c.add_argument("--fill-method", choices=("local", "global"), default="local",
                   help="fill: moving-window (local, default) or global kriging")
    c.add_argument("--fill-nu", choices=("0.5", "1.5", "2.5", "auto"), default="0.5",
                   help="fill: the smoothness (default 0.5; auto by the self-check)")
    c.add_argument("--no-self-check", dest="self_check", action="store_false",
                   help="fill: skip the self-check on held-out points")
    b.set_defaults(func=run)


def _cores() -> int:
    """The cores this process may use (as :func:`roughgp.batch.engine.default_workers`, without
    importing it for --help)."""
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except AttributeError:  # pragma: no cover - not Linux
        return max(1, os.cpu_count() or 1)


def plan_of(args):
    """The :class:`roughgp.batch.records.Plan` of the options."""
    from roughgp.batch.records import Plan
    if args.predictive and args.predictive_from == "tiles" and not args.part:
        raise UsageError("--predictive-from tiles draws the tiles of the part each model was "
                         "fitted on: give --part (the check is then held out)")
    operators = {"form": args.form, "degree": args.degree, "axis": args.axis}
    if args.s_filter is not None:
        operators["s"] = args.s_filter
    if args.l_filter is not None:
        operators["l"] = args.l_filter
    read = {"kind": args.kind, "spacing": args.spacing, "channel": args.channel,
            "unit": args.unit}
    if args.spurious:   # only when given: the plans (and records) of earlier batches stay current
        read.update(spurious=True, form=args.form)
    options = {"read": read,
               "texture": {**operators, "unfiltered": args.unfiltered, "l_kind": args.l_kind},
               "fit": {**operators, "model": args.rung, "marginal": args.marginal,
                       "nu": args.nu, "likelihood": args.likelihood, "block": args.block,
                       "blocks": args.blocks, "mixtures": args.mixtures,
                       "candidates": args.candidates,
                       **({"part": args.part} if args.part else {}),
                       **({"anchors": list(args.anchors)} if args.anchors else {})},
               "check": {"simulations": args.simulations, "plot": args.plots,
                         **({"predictive": args.predictive,
                             "predictive_from": args.predictive_from}
                            if args.predictive else {})},
               "fill": {"form": args.form, "degree": args.degree, "axis": args.axis,
                        "method": args.fill_method,
                        "nu": args.fill_nu if args.fill_nu == "auto" else float(args.fill_nu),
                        "self_check": args.self_check, "block": args.block,
                        "blocks": args.blocks}}
    if args.predictive:  # only when given: the plans (and records) of earlier batches stay current
        options["simulate"] = {"predictive_from": args.predictive_from}
    options = {k: v for k, v in options.items() if k == "read" or k in args.steps}
    try:
        return Plan(steps=args.steps, seed=args.seed, options=options)
    except ValueError as exc:
        raise UsageError(f"--steps: {exc}") from None


def _check_folder(out: Path, files) -> None:
    """The output folder: not a file (an input above all), not an input's folder's file."""
    if out.exists() and not out.is_dir():
        what = ("an input file" if any(os.path.abspath(f) == os.path.abspath(out)
                                       for f in files) else "a file")
        raise UsageError(f"--out: {out} is {what}; give a folder (roughgp never writes over "
                         f"its input)")
    folder = out
    while not folder.exists() and folder != folder.parent:
        folder = folder.parent
    if not folder.is_dir() or not os.access(folder, os.W_OK | os.X_OK):
        raise UsageError(f"--out: cannot write into {out}: {folder} is not a writable folder")


def _clock(seconds) -> str:
    if seconds is None:
        return "--:--"
    seconds = int(round(seconds))
    return f"{seconds // 3600}:{seconds // 60 % 60:02d}:{seconds % 60:02d}"


def run(args) -> int:
    """``roughgp batch FILES... --out FOLDER``."""
    from roughgp.batch.engine import default_workers, expand_inputs, run_batch
    if args.scheduler is not None and args.workers is not None:
        raise UsageError("--workers sizes the local cluster; --scheduler uses an existing one: "
                         "give one of them")
    if args.anchors is not None:
        if args.rung not in ("field", "population"):
            raise UsageError(f"--anchors applies to --model field and population only (got "
                             f"--model {args.rung})")
        if not all(1 <= a <= MAX_ANCHORS for a in args.anchors):
            raise UsageError(f"--anchors must be two integers in [1, {MAX_ANCHORS}], got "
                             f"{args.anchors[0]} {args.anchors[1]}")
    plan = plan_of(args)
    out = Path(args.out)
    files = expand_inputs(args.files, exclude=out if out.is_dir() else None)
    if not files:
        raise UsageError(f"FILES: no file matched {' '.join(args.files)} (give files, quoted "
                         f"globs such as 'maps/*.x3p', or folders)")
    _check_folder(out, files)
    workers = args.workers or default_workers()
    where = (f"the Dask scheduler at {args.scheduler}" if args.scheduler else
             f"a local Dask cluster of {workers} worker process{'es' * (workers != 1)}")
    err(f"batch: {len(files)} file{'s' * (len(files) != 1)}, steps {','.join(plan.steps)}, "
        f"seed {plan.seed}, on {where}; into {out}/")

    def progress(done, failed, running, total, eta, record):
        if record is None:
            if done:
                err(f"  {done} of {total} already done (current records in {out}/records): "
                    f"skipped")
            return
        name = Path(record.get("path", "?")).name
        what = "ok" if record.get("status") == "done" else f"FAILED: {record.get('error')}"
        seconds = (record.get("seconds") or {}).get("total")
        took = f" ({seconds:.1f} s)" if seconds is not None else ""
        err(f"  [{done}/{total}] done {done - failed}, failed {failed}, running {running}, "
            f"ETA {_clock(eta)}: {name} {what}{took}")

    def started(dashboard):
        if dashboard:
            err(f"the Dask dashboard: {dashboard}")

    result = run_batch(files, plan, out, workers=None if args.scheduler else workers,
                       scheduler=args.scheduler, progress=progress, started=started)
    print(f"{len(files)} files: {len(files) - result.failed} done ({result.skipped} from "
          f"earlier runs), {result.failed} failed")
    for record in result.records:
        if record.get("status") != "done":
            print(f"  failed: {record.get('path')}: {record.get('error')}")
    for path in result.tables:
        print(f"wrote {path}")
    return exit_code(result.failed)
