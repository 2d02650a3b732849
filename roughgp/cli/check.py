"""``roughgp check MODEL.json FILE``: does the fitted model reproduce the measurement?
(:func:`roughgp.check`: :func:`roughgp.checking.model_check.check_model`, or the calibrated
check). Argument handling and the table only.
"""

from __future__ import annotations

import math
import time

from roughgp.cli.bounds import bounds_text
from roughgp.cli.options import add_spurious_options, load_model, read_input, remove_spurious
from roughgp.cli.output import (
    UsageError,
    add_force_option,
    check_outputs,
    err,
    print_wrapped,
    write_json,
)
from roughgp.common.atomic import atomic_output

__all__ = ['add_parser', 'run']

_CHECK = """\
Place the texture parameters of a measurement among those of N simulations of a fitted
model (a model file of 'roughgp fit'): the simulations go through the rest of the
measurement's operator chain (its holes, form removal, S- and L-filters) as the measurement
went; for each parameter the measured value, the simulated range
and median, and the measurement's rank among the simulations. A parameter whose measured
value lies outside the simulated range is named: with N simulations a model that describes
the measurement puts it outside with probability 2 / (N + 1) (10 % for the default 19), so
an outside parameter is evidence against the model, an inside one no proof for it. A
Gaussian model (eq 8) shows here what it misses: skewness, kurtosis, Spk / Svk. Holes: the
height parameters are of the measured points (the simulations get the same holes), Sal,
Str, Std of both with the holes set to the mean height. --plot writes a figure (.png, .pdf, .svg).

A model fitted to this very measurement has seen it, and the plain check then says
"outside" less often than 2 / (N + 1) for some parameters (Sq, Sa, Sk: 6.4 to 6.9 %
instead of 10 % on synthetic maps). --calibrate B draws B measurements from the
model with the measurement's holes, refits each the way the model was fitted and checks
it against its refit: a parameter is then outside when the measurement is more extreme
than 90 % of those copies (a calibrated p-value of at most 0.1). Each copy costs a fit and
N simulations. Surface models of stage 'form-removed' only. Measured on synthetic maps, it
brings Sq and Sa nearer 10 % but says "outside" for Sal too often: the book's chapter "Does
the model check say no when it should?" shows both.

example:
  roughgp check land-model.json land.x3p --simulations 19 --seed 0 --plot check.png
  roughgp check land-model.json land.x3p --calibrate 19"""


def add_parser(sub, formatter, input_epilog, add_input_options) -> None:
    """Add ``check`` to the sub-command parsers ``sub``."""
    c = sub.add_parser("check", formatter_class=formatter, description=_CHECK,
                       epilog=input_epilog,
                       help="texture parameters of a measurement against a model's simulations")
    c.add_argument("model", metavar="MODEL.json", help="a model file of 'roughgp fit'")
    add_input_options(c, kind=False, what="the measurement the model was fitted to (or another)")
    c.add_argument("--simulations", type=int, default=19, metavar="N",
                   help=f"simulations of the model, {bounds_text('--simulations')} (default "
                        f"19)")
    c.add_argument("--seed", type=int, default=0, metavar="S",
                   help=f"seed of the simulations, {bounds_text('--seed')} (default 0)")
    c.add_argument("--calibrate", type=int, metavar="B",
                   help=f"calibrate the check by B refitted bootstrap copies, "
                        f"{bounds_text('--calibrate')} (19 makes the level a whole count; "
                        f"default: the plain check)")
    c.add_argument("--plot", metavar="FIGURE", help="write the figure (.png, .pdf or .svg)")
    c.add_argument("--json", metavar="OUT", help="also write the table as JSON (.json)")
    add_spurious_options(c)
    add_force_option(c)
    c.set_defaults(func=run)


def _spacing_note(heights, model) -> str | None:
    """A note when the file's spacing is not the model's (the simulations are drawn at the
    file's, so a spacing the file does not state, assumed 1 um, compares other lengths)."""
    spacing = heights.spacing if model.kind == "surface" else (heights.spacing[-1],)
    if all(abs(a - b) <= 1e-6 * b for a, b in zip(spacing, model.spacing)):
        return None
    given = ", ".join(f"{d:g}" for d in spacing)
    fitted = ", ".join(f"{d:g}" for d in model.spacing)
    return (f"the file's spacing {given} um ({heights.spacing_source}) is not the model's "
            f"{fitted} um (the data it was fitted to): the simulations are drawn at the file's")


def run(args) -> int:
    """``roughgp check MODEL FILE``."""
    from roughgp.api import check
    from roughgp.checking.model_check import plot_model_check
    json_out, plot = check_outputs(("--json", args.json, "json"), ("--plot", args.plot, "plot"),
                                   inputs=(args.file, args.model), force=args.force)
    model = load_model(args.model)
    heights = read_input(args)  # what the file holds: a 2-column profile is no 512 x 2 surface
    if heights.kind != model.kind:
        raise UsageError(f"{args.file} holds a {heights.kind} ("
                         f"{' x '.join(map(str, heights.z.shape))} points); {args.model} is a "
                         f"{model.kind} model: check it against a {model.kind}")
    if args.calibrate is not None:
        from roughgp.checking.calibrated import refusal
        why = refusal(model)
        if why:
            raise UsageError(f"--calibrate: {args.model}: {why}")
    spacing_note = _spacing_note(heights, model)
    z = remove_spurious(args, heights, model.cutoffs.get("form", "plane"))  # the model's F
    err(f"simulating {args.simulations} {model.kind}s of {' x '.join(map(str, heights.z.shape))}"
        f" points from {args.model} ...")
    start = time.perf_counter()
    spacing = heights.spacing if model.kind == "surface" else (heights.spacing[-1],)
    calibrated = None
    if args.calibrate is None:
        result = check(model, z, spacing, n_simulations=args.simulations, seed=args.seed)
    else:
        calibrated = _calibrated(model, z, spacing, args, start)
        result = calibrated.check
    err(f"({time.perf_counter() - start:.1f} s)")
    print(f"{args.file} against {args.simulations} simulations of {args.model}")
    print_wrapped(f"model: {model.describe()}")
    print_wrapped("operators (on both): " + "; ".join(result.operators))
    for note in (*((spacing_note,) if spacing_note else ()), *result.notes):
        print_wrapped(f"note: {note}")
    head = f"  {'':5} {'measured':>11} {'sim. min':>11} {'median':>11} {'sim. max':>11} " \
           f"{'rank':>8}"
    print(head + ("" if calibrated is None else f" {'p (cal.)':>8}"))
    for p in result.parameters:
        if calibrated is None:
            verdict, extra = ("OUTSIDE" if p.outside else ""), ""
        else:
            verdict = "OUTSIDE" if p.name in calibrated.outside else ""
            extra = f" {_p(calibrated.p_values[p.name])}"
        print(f"  {p.name:<5} {_num(p.measured)} {_num(p.low)} {_num(p.median)} "
              f"{_num(p.high)} {p.rank:>4}/{args.simulations:<3}{extra} {verdict} "
              f"{p.unit}".rstrip())
    if calibrated is None:
        outside = result.outside
        print_wrapped(("outside the simulated range: " + ", ".join(outside)) if outside else
                      "every parameter lies within the simulated range")
    else:
        _calibrated_verdict(calibrated)
    if json_out is not None:
        record = result.to_dict() if calibrated is None else calibrated.to_dict()
        write_json(json_out, {"file": str(args.file), "model": str(args.model),
                              "seed": args.seed, **record})
    if plot is not None:
        import matplotlib.pyplot as plt
        with atomic_output(plot) as partial:  # whole or not at all; missing folders made
            figure = plot_model_check(result, partial, title=f"{args.file}: the measurement "
                                      f"(line) among {args.simulations} simulations")
        plt.close(figure)
        err(f"wrote {plot}")
    return 0


def _calibrated(model, z, spacing, args, start):
    """The calibrated check, a progress line a bootstrap copy."""
    from roughgp.api import check

    def progress(b, total):
        err(f"  bootstrap copy {b}/{total} refitted and checked "
            f"({time.perf_counter() - start:.0f} s)")
    err(f"then {args.calibrate} bootstrap copies of the measurement from the model, each "
        f"refitted and checked against {args.simulations} simulations of its refit ...")
    if args.calibrate < 9:  # p <= 0.1 needs u (B + 1) <= 1 even beyond every copy
        err(f"note: with {args.calibrate} copies even a measurement more extreme than all of "
            f"them is called outside only with probability {(args.calibrate + 1) / 10:g} "
            f"(--calibrate 9 or more removes that limit)")
    try:
        return check(model, z, spacing, n_simulations=args.simulations, seed=args.seed,
                     calibrate=args.calibrate, progress=progress)
    except ValueError as error:  # a copy the refit refuses (too few points, say)
        raise UsageError(f"--calibrate: {error}") from None


def _calibrated_verdict(calibrated) -> None:
    plain = calibrated.check.outside
    print_wrapped(f"calibrated by {calibrated.n_bootstrap} refitted bootstrap copies: p (cal.) "
                  f"is the share of copies at least as extreme as the measurement (ties "
                  f"broken by the seed); outside at p <= {calibrated.level:g}")
    outside = calibrated.outside
    print_wrapped(("outside (calibrated): " + ", ".join(outside)) if outside else
                  "no parameter is outside (calibrated)")
    print_wrapped("outside the simulated range (the plain check): "
                  + (", ".join(plain) if plain else "none"))


def _p(value) -> str:
    return f"{value:>8.3f}" if math.isfinite(value) else f"{'nan':>8}"


def _num(value) -> str:
    return f"{value:>11.4g}" if math.isfinite(value) else f"{'nan':>11}"
