"""``roughgp check MODEL.json FILE``: does the fitted model reproduce the measurement?
(:func:`roughgp.check`: :func:`roughgp.checking.model_check.check_model`, or the calibrated
check). Argument handling and the table only.
"""

from __future__ import annotations

import math
import time

from roughgp.cli.bounds import bounds_text, integer
from roughgp.cli.options import (
    PREDICTIVE_SOURCES,
    add_part_option,
    add_spurious_options,
    crop_to_part,
    flagged_output,
    load_model,
    read_input,
    remove_spurious,
    write_flagged,
)
from roughgp.cli.output import (
    UsageError,
    add_force_option,
    check_outputs,
    err,
    print_wrapped,
    write_json,
)
from roughgp.cli.pace import Pace
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

Out of sample: a model that describes the surface, not only the crop it saw, reproduces
other parts of it too. Fit on a part (roughgp fit ground FILE --part left), then --held-out
checks the model on that part and on the part it did not see (the other half), side by
side; --part P checks any part. --predictive B draws the simulations from B refits of
bootstrap measurements of the model (the fit's uncertainty carried: plug-in simulations of
one fitted model are too alike for another crop); with --predictive-from sandwich (eq 18
models) from B parameter sets drawn from the Whittle likelihood's sandwich covariance on the
fitted grid instead (no refits: about half the time of 9 refits on 256 x 256 points); with
--predictive-from tiles (with --held-out) from B copies of the model given the variance and
the heights of the fitted part's 4 x 4 tiles drawn with replacement, and a measured PSD their
spectrum's shape too (the crop-to-crop variation the fitted part shows, and the fit's; the
variance's spread widened to a crop's, as the model's own draws measure it).
--tiles M N cuts the map into M x N tiles and ranks each tile's Sq, Sal, Str and Std among
the same tile of the simulations: where on the map the model fails (--plot draws the
tiles). How often each says "outside" on surfaces of known models: the chapter "Does the
model check say no when it should?".

examples:
  roughgp check land-model.json land.x3p --simulations 19 --seed 0 --plot check.png
  roughgp check land-model.json land.x3p --calibrate 19
  roughgp fit ground map.x3p --part left --out left.json
  roughgp check left.json map.x3p --held-out --predictive 9
  roughgp check left.json map.x3p --held-out --predictive 19 --predictive-from sandwich
  roughgp check left.json map.x3p --held-out --predictive 19 --predictive-from tiles
  roughgp check left.json map.x3p --tiles 2 4 --plot tiles.png"""


def add_parser(sub, formatter, input_epilog, add_input_options) -> None:
    """Add ``check`` to the sub-command parsers ``sub``."""
    c = sub.add_parser("check", formatter_class=formatter, description=_CHECK,
                       epilog=input_epilog,
                       help="texture parameters of a measurement against a model's simulations")
    c.add_argument("model", metavar="MODEL.json", help="a model file of 'roughgp fit'")
    add_input_options(c, kind=False, what="the measurement the model was fitted to (or another)")
    c.add_argument("--simulations", type=integer("--simulations"), default=19, metavar="N",
                   help=f"simulations of the model, {bounds_text('--simulations')} (default "
                        f"19)")
    c.add_argument("--seed", type=integer("--seed"), default=0, metavar="S",
                   help=f"seed of the simulations, {bounds_text('--seed')} (default 0)")
    c.add_argument("--calibrate", type=integer("--calibrate"), metavar="B",
                   help=f"calibrate the check by B refitted bootstrap copies, "
                        f"{bounds_text('--calibrate')} (19 makes the level a whole count; "
                        f"default: the plain check)")
    c.add_argument("--held-out", action="store_true",
                   help="check the model on the part of FILE it was fitted on (fit --part, "
                        "a half) and on the other half, side by side")
    add_part_option(c)
    c.add_argument("--predictive", type=integer("--predictive"), metavar="B",
                   help=f"draw the simulations from B refits of bootstrap measurements of the "
                        f"model, {bounds_text('--predictive')} (default: the plug-in model)")
    c.add_argument("--predictive-from", choices=PREDICTIVE_SOURCES,
                   default="refits",
                   help="how --predictive draws the models: 'refits' (B bootstrap refits, "
                        "any rung --calibrate refits), 'sandwich' (eq 18: B parameter sets "
                        "from the Whittle sandwich covariance, no refits) or 'tiles' (with "
                        "--held-out; measured PSD or eq 18: the fitted part's 4 x 4 tiles "
                        "drawn with replacement, their variance and heights, and a measured PSD "
                        "their spectrum's shape) (default refits)")
    c.add_argument("--tiles", type=integer("--tiles"), nargs=2, metavar=("M", "N"),
                   help="rank each of M x N tiles' Sq, Sal, Str, Std among the same tile of "
                        "the simulations (tiles of at least 16 x 16 points)")
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


def _refuse_combinations(args) -> None:
    """The out-of-sample options among themselves and with --calibrate."""
    if args.calibrate is not None:
        for option, given in (("--held-out", args.held_out), ("--tiles", args.tiles),
                              ("--predictive", args.predictive)):
            if given:
                raise UsageError(f"--calibrate calibrates the plain check of one measurement; "
                                 f"it cannot be combined with {option}")
    if args.predictive_from != "refits" and args.predictive is None:
        raise UsageError(f"--predictive-from {args.predictive_from} chooses how --predictive B "
                         f"draws its models: give --predictive B too")
    if args.predictive_from == "tiles" and not args.held_out:
        raise UsageError("--predictive-from tiles draws the tiles of the part the model was "
                         "fitted on (fit ground --part): give --held-out")
    if args.held_out and args.part is not None:
        raise UsageError("--held-out checks the fitted part and the other half; --part checks "
                         "one part: give one of them")
    if args.held_out and args.tiles:
        raise UsageError("--tiles checks tiles of FILE (or of --part); it cannot be combined "
                         "with --held-out")


def _fitted_part(model, heights, args):
    """The part the model was fitted on (its model file's data.part), for --held-out."""
    from roughgp.checking.held_out import Part
    record = model.data.get("part") if isinstance(model.data, dict) else None
    if record is None:
        raise UsageError(f"--held-out: {args.model} was fitted on a whole map (its data record "
                         f"no part): fit it with --part left (or right, top, bottom) to hold "
                         f"out the other half")
    try:
        part = Part.from_dict(record)
    except ValueError as error:
        raise UsageError(f"--held-out: {args.model}: {error}") from None
    if tuple(part.of_shape) != heights.z.shape:
        raise UsageError(f"--held-out: {args.model} was fitted on part {part.name} of a "
                         f"{part.of_shape[0]} x {part.of_shape[1]} map; {args.file} is "
                         f"{' x '.join(map(str, heights.z.shape))}")
    return part


def _predictive_models(model, args, start, fitted=None):
    from roughgp.checking.predictive import fitted_shape, predictive_models, predictive_refusal
    refits = args.predictive_from == "refits"
    option = "--predictive" if refits else f"--predictive-from {args.predictive_from}"
    why = predictive_refusal(model) if refits else None
    if why:
        raise UsageError(f"--predictive: {args.model}: {why}")
    shape = fitted_shape(model, None)  # None: predictive_models says why
    spread = None
    if args.predictive_from == "tiles":
        from roughgp.checking.tile_bootstrap import tile_spread_factor
        err(f"drawing {args.predictive} models from the fitted part's tiles, drawn with "
            f"replacement (their variance and heights; a measured PSD their spectrum's shape "
            f"too) ...")
        try:
            spread = tile_spread_factor(model, fitted[0], spacing=fitted[1], seed=args.seed)
        except ValueError as error:
            raise UsageError(f"{option}: {args.model}: {error}") from None
        err(f"  the tiles' variance ratios raised to {spread:.2f}: on the model's own draws a "
            f"crop's log variance spreads {spread:.2f} times as wide as its tiles' bootstrap "
            f"(the waves longer than a tile)")
    elif shape is not None and refits:
        err(f"refitting {args.predictive} bootstrap measurements of {shape[0]} x {shape[1]} "
            f"points drawn from the model (the fit's uncertainty) ...")
    elif shape is not None:
        err(f"drawing {args.predictive} parameter sets of the model from its Whittle sandwich "
            f"covariance on the fitted {shape[0]} x {shape[1]} grid (the fit's uncertainty) ...")

    def progress(b, total):
        err(f"  bootstrap measurement {b}/{total} refitted ({time.perf_counter() - start:.0f} s)")
    try:
        models, held = predictive_models(model, args.predictive, source=args.predictive_from,
                                         seed=args.seed, progress=progress, fitted=fitted,
                                         spread=spread)
    except ValueError as error:
        raise UsageError(f"{option}: {args.model}: {error}") from None
    if held:
        err(f"  held at the fit (the fitted grid does not determine them): {', '.join(held)}")
    return models


def run(args) -> int:
    """``roughgp check MODEL FILE``."""
    json_out, plot, flagged_out = check_outputs(
        ("--json", args.json, "json"), ("--plot", args.plot, "plot"), flagged_output(args),
        inputs=(("FILE", args.file), ("MODEL", args.model)), force=args.force)
    _refuse_combinations(args)
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
    fitted_part = _fitted_part(model, heights, args) if args.held_out else None
    whole = heights
    heights, part = crop_to_part(args, heights)
    if args.tiles:
        from roughgp.checking.tiles import tile_slices
        if model.kind != "surface":
            raise UsageError(f"--tiles cuts a surface into tiles; {args.model} is a "
                             f"{model.kind} model")
        try:
            tile_slices(heights.z.shape, args.tiles)
        except ValueError as error:
            raise UsageError(f"--{error}") from None
    spacing_note = _spacing_note(heights, model)
    # found on the whole file, --part or not (as fit ground --part), with the model's F
    z, found = remove_spurious(args, whole, model.cutoffs.get("form", "plane"))
    z = z if part is None else part.cut(z)
    start = time.perf_counter()
    spacing = heights.spacing if model.kind == "surface" else (heights.spacing[-1],)
    fitted = None if fitted_part is None else (fitted_part.cut(z), spacing)
    models = None if args.predictive is None else _predictive_models(model, args, start,
                                                                     fitted)
    err(f"simulating {args.simulations} {model.kind}s of {' x '.join(map(str, z.shape))}"
        f" points from {args.model} ...")
    draws = ("plug-in" if models is None else "predictive" if
             args.predictive_from == "refits" else f"predictive ({args.predictive_from})")
    if args.tiles:
        code = _tiles(args, model, z, spacing, models, start, json_out, plot, spacing_note,
                      draws)
    elif fitted_part is not None:
        code = _held_out(args, model, z, spacing, models, fitted_part, start, json_out, plot,
                         spacing_note, draws)
    else:
        code = _whole(args, model, z, spacing, models, start, json_out, plot, spacing_note,
                      part, draws)
    write_flagged(flagged_out, found, args, whole)
    return code


def _whole(args, model, z, spacing, models, start, json_out, plot, spacing_note, part,
           draws) -> int:
    """``check MODEL FILE`` (plain or ``--calibrate``): one table of the whole map."""
    from roughgp.api import check
    calibrated = None
    if args.calibrate is None:
        result = check(model, z, spacing, n_simulations=args.simulations, seed=args.seed,
                       models=models, progress=Pace("simulations (each drawn and measured)",
                                                    "a smaller --simulations or --part"))
    else:
        calibrated = _calibrated(model, z, spacing, args, start)
        result = calibrated.check
    err(f"({time.perf_counter() - start:.1f} s)")
    where = "" if part is None else f" (part {part.name})"
    print(f"{args.file}{where} against {args.simulations} {draws} simulations of {args.model}")
    _print_head(model, result, spacing_note)
    _print_table(result, args.simulations, calibrated)
    if calibrated is None:
        outside = result.outside
        print_wrapped(("outside the simulated range: " + ", ".join(outside)) if outside else
                      "every parameter lies within the simulated range")
    else:
        _calibrated_verdict(calibrated)
    if json_out is not None:
        record = result.to_dict() if calibrated is None else calibrated.to_dict()
        write_json(json_out, {"file": str(args.file), "model": str(args.model),
                              "seed": args.seed, "simulations": draws,
                              **({"part": part.to_dict()} if part else {}), **record})
    if plot is not None:
        _plot_check(result, plot, f"{args.file}{where}: the measurement (line) among "
                    f"{args.simulations} {draws} simulations")
    return 0


def _print_head(model, result, spacing_note) -> None:
    print_wrapped(f"model: {model.describe()}")
    print_wrapped("operators (on both): " + "; ".join(result.operators))
    for note in (*((spacing_note,) if spacing_note else ()), *result.notes):
        print_wrapped(f"note: {note}")


def _print_table(result, n_simulations, calibrated=None) -> None:
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
              f"{_num(p.high)} {p.rank:>4}/{n_simulations:<3}{extra} {verdict} "
              f"{p.unit}".rstrip())


def _plot_check(result, plot, title) -> None:
    import matplotlib.pyplot as plt

    from roughgp.checking.model_check import plot_model_check
    with atomic_output(plot) as partial:  # whole or not at all; missing folders made
        figure = plot_model_check(result, partial, title=title)
    plt.close(figure)
    err(f"wrote {plot}")


def _describe(part) -> str:
    return (f"{part.name}: rows {part.rows[0]}:{part.rows[1]}, columns "
            f"{part.cols[0]}:{part.cols[1]}")


def _held_out(args, model, z, spacing, models, fitted_part, start, json_out, plot,
              spacing_note, draws) -> int:
    """``check --held-out``: the fitted part and the other half, one table each."""
    from roughgp.checking.held_out import held_out_check
    try:
        result = held_out_check(model, z, spacing, fitted_part=fitted_part,
                                n_simulations=args.simulations, seed=args.seed, models=models)
    except ValueError as error:
        raise UsageError(f"--held-out: {error}") from None
    err(f"({time.perf_counter() - start:.1f} s)")
    print(f"{args.file} against {args.simulations} {draws} simulations of {args.model}, on the "
          f"part it was fitted on and on the part it did not see")
    _print_head(model, result.held_out, spacing_note)
    for label, part, check in (("fitted", result.fitted_part, result.fitted),
                               ("held out", result.held_out_part, result.held_out)):
        print(f"{label} part ({_describe(part)}):")
        _print_table(check, args.simulations)
    for label, check in (("fitted part", result.fitted), ("held-out part", result.held_out)):
        print_wrapped(f"outside on the {label}: " + (", ".join(check.outside) or "none"))
    print_wrapped(f"each parameter lies outside with probability {2 / (args.simulations + 1):.0%}"
                  f" for a model that describes the surface; the held-out part is the test "
                  f"(the fitted one the model has seen)")
    if json_out is not None:
        write_json(json_out, {"file": str(args.file), "model": str(args.model),
                              "seed": args.seed, "simulations": draws, **result.to_dict()})
    if plot is not None:
        _plot_check(result.held_out, plot, f"{args.file}, held-out part {fitted_part.name!s} "
                    f"-> {result.held_out_part.name}: the measurement (line) among "
                    f"{args.simulations} {draws} simulations")
    return 0


def _tiles(args, model, z, spacing, models, start, json_out, plot, spacing_note,
           draws) -> int:
    """``check --tiles M N``: the outside tiles per parameter, as counts and a text map."""
    from roughgp.checking.tiles import tile_check
    result = tile_check(model, z, spacing, tiles=tuple(args.tiles),
                        n_simulations=args.simulations, seed=args.seed, models=models)
    err(f"({time.perf_counter() - start:.1f} s)")
    m, n = result.tiles
    print(f"{args.file} in {m} x {n} tiles against {args.simulations} {draws} simulations of "
          f"{args.model}")
    print_wrapped(f"model: {model.describe()}")
    for note in (*((spacing_note,) if spacing_note else ()), *result.notes):
        print_wrapped(f"note: {note}")
    print_wrapped(f"each tile outside with probability {result.expected_share:.0%} for a model "
                  f"that describes the surface; map: + above every simulation, - below, . within")
    marks = {1: "+", -1: "-", 0: "."}
    for k, name in enumerate(result.names):
        side = result.side[..., k]
        print(f"  {name:<4} {int((side != 0).sum())} of {side.size} tiles outside")
        for row in side:
            print("       " + " ".join(marks[int(s)] for s in row))
    if json_out is not None:
        write_json(json_out, {"file": str(args.file), "model": str(args.model),
                              "seed": args.seed, "simulations": draws, **result.to_dict()})
    if plot is not None:
        import matplotlib.pyplot as plt

        from roughgp.checking.tiles import plot_tile_check
        with atomic_output(plot) as partial:
            figure = plot_tile_check(result, partial, title=f"{args.file}: tiles outside "
                                     f"{args.simulations} {draws} simulations (red above, "
                                     f"blue below)")
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
                     calibrate=args.calibrate,
                     progress=Pace("bootstrap copies, each refitted and checked",
                                   "a smaller --calibrate, --simulations or --part", progress))
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
