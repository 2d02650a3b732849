"""``roughgp check MODEL.json FILE``: does the fitted model reproduce the measurement?
(:func:`roughgp.beyond.measured.check.check_model`). Argument handling and the table only.
"""

from __future__ import annotations

import math
import time

from roughgp.cli.options import (
    add_spurious_options,
    bounds_text,
    load_model,
    read_input,
    remove_spurious,
)
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

example:
  roughgp check land-model.json land.x3p --simulations 19 --seed 0 --plot check.png"""


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
    from roughgp.beyond.measured.check import check_model, plot_model_check
    json_out, plot = check_outputs(("--json", args.json, "json"), ("--plot", args.plot, "plot"),
                                   inputs=(args.file, args.model), force=args.force)
    model = load_model(args.model)
    heights = read_input(args)  # what the file holds: a 2-column profile is no 512 x 2 surface
    if heights.kind != model.kind:
        raise UsageError(f"{args.file} holds a {heights.kind} ("
                         f"{' x '.join(map(str, heights.z.shape))} points); {args.model} is a "
                         f"{model.kind} model: check it against a {model.kind}")
    spacing_note = _spacing_note(heights, model)
    z = remove_spurious(args, heights, model.cutoffs.get("form", "plane"))  # the model's F
    err(f"simulating {args.simulations} {model.kind}s of {' x '.join(map(str, heights.z.shape))}"
        f" points from {args.model} ...")
    start = time.perf_counter()
    result = check_model(model, z, heights.spacing if model.kind == "surface"
                         else (heights.spacing[-1],), n_simulations=args.simulations,
                         seed=args.seed)
    err(f"({time.perf_counter() - start:.1f} s)")
    print(f"{args.file} against {args.simulations} simulations of {args.model}")
    print_wrapped(f"model: {model.describe()}")
    print_wrapped("operators (on both): " + "; ".join(result.operators))
    for note in (*((spacing_note,) if spacing_note else ()), *result.notes):
        print_wrapped(f"note: {note}")
    print(f"  {'':5} {'measured':>11} {'sim. min':>11} {'median':>11} {'sim. max':>11} "
          f"{'rank':>8}")
    for p in result.parameters:
        verdict = "OUTSIDE" if p.outside else ""
        print(f"  {p.name:<5} {_num(p.measured)} {_num(p.low)} {_num(p.median)} "
              f"{_num(p.high)} {p.rank:>4}/{args.simulations:<3} {verdict} {p.unit}".rstrip())
    outside = result.outside
    print_wrapped(("outside the simulated range: " + ", ".join(outside)) if outside else
                  "every parameter lies within the simulated range")
    if json_out is not None:
        write_json(json_out, {"file": str(args.file), "model": str(args.model),
                              "seed": args.seed, **result.to_dict()})
    if plot is not None:
        import matplotlib.pyplot as plt
        with atomic_output(plot) as partial:  # whole or not at all; missing folders made
            figure = plot_model_check(result, partial, title=f"{args.file}: the measurement "
                                      f"(line) among {args.simulations} simulations")
        plt.close(figure)
        err(f"wrote {plot}")
    return 0


def _num(value) -> str:
    return f"{value:>11.4g}" if math.isfinite(value) else f"{'nan':>11}"
