"""Options that several commands share: the F-, S- and L-operators (texture, fit), a model
file (simulate, check, fill), the spurious points and the seed (the bounds of every numeric
option are :mod:`roughgp.cli.bounds`'s). Argument handling only.
"""

from __future__ import annotations

import argparse
import math
import secrets

import numpy as np

from roughgp.cli.bounds import bounds_text, integer
from roughgp.cli.output import UsageError, err
from roughgp.common.checks import check_scale

__all__ = ["add_part_option", "crop_to_part", "cutoff", "add_form_options",
           "add_operator_options", "operator_settings", "check_cutoffs", "load_model",
           "check_scales", "seed_or_fresh", "read_input", "Given", "add_l_kind_options",
           "add_spurious_options", "fitted_size", "flagged_output", "remove_spurious",
           "write_flagged", "PREDICTIVE_SOURCES"]

#: how ``--predictive-from`` (check, batch, simulate) draws the models that carry the fit's
#: uncertainty: :data:`roughgp.checking.predictive.SOURCES`, written out so that the parser does
#: not import the checking package at start-up (a test holds them equal)
PREDICTIVE_SOURCES = ("refits", "sandwich", "tiles")


def seed_or_fresh(seed):
    """``seed``, or a fresh one (printed, so the draw can be repeated) when it is None."""
    if seed is None:
        seed = secrets.randbelow(2 ** 31)
        err(f"seed: {seed} (pass --seed {seed} to draw the same surface again)")
    return seed


def check_scales(*options) -> None:
    """Each ``(option, value, zero)`` whose value is given: a finite number in the library's
    range of scales (:data:`roughgp.common.checks.SCALE_RANGE`; 0 too where ``zero``), or a
    :class:`UsageError` that names the option."""
    for option, value, zero in options:
        if value is None:
            continue
        try:
            check_scale(option, value, zero=zero)
        except ValueError as exc:
            unit = " (um^2)" if "variance" in option else " (um)"
            raise UsageError(f"{exc}{unit}") from None


def cutoff(text):
    """A nesting index option: ``auto``, ``none`` or a length in um (> 0)."""
    if text in ("auto", "none"):
        return text
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected auto, none or a length in um, got "
                                         f"{text!r}") from None
    if not (math.isfinite(value) and value > 0):
        raise argparse.ArgumentTypeError(f"a nesting index must be > 0 (um), got {text!r}")
    return value


def add_form_options(parser, what="F-operator") -> None:
    """--form, --degree, --axis: the F-operator."""
    parser.add_argument("--form", choices=("plane", "polynomial", "cylinder", "none"),
                        default="plane", action=Given,
                        help=f"{what} (default plane: a line for a profile)")
    parser.add_argument("--degree", type=integer("--degree"), default=2, metavar="N", action=Given,
                        help=f"degree of --form polynomial, {bounds_text('--degree')} "
                             f"(default 2)")
    parser.add_argument("--axis", choices=("auto", "x", "y"), default="auto", action=Given,
                        help="the axis of --form cylinder (default auto: the better fit)")


def add_operator_options(parser, *, s_default="auto", l_default="auto") -> None:
    """--form, --degree, --axis, --s-filter, --l-filter."""
    add_form_options(parser)
    parser.add_argument("--s-filter", type=cutoff, default=s_default, metavar="S",
                        action=Given,
                        help=f"S-filter nesting index in um ({bounds_text('--s-filter')}, at "
                             f"most the field's length), auto or none (default {s_default})")
    parser.add_argument("--l-filter", type=cutoff, default=l_default, metavar="L",
                        action=Given,
                        help=f"L-filter nesting index (cut-off) in um ("
                             f"{bounds_text('--l-filter')}, at most the field's length), auto "
                             f"or none (default {l_default})")


def operator_settings(args) -> dict:
    """``form``, ``s``, ``l``, ``degree``, ``axis`` for the library from the options."""
    def length(value):
        return None if value == "none" else value

    return {"form": None if args.form == "none" else args.form, "s": length(args.s_filter),
            "l": length(args.l_filter), "degree": args.degree, "axis": args.axis}


def read_input(args, kind="auto"):
    """The measurement of ``args.file`` (:func:`roughgp.read` with the input options).
    ``--unit`` is the reader's to apply or refuse: it sets the heights' unit of ``.npy``, text
    and instrument files, and an ``.x3p`` (metres) refuses it."""
    from roughgp.api import read
    return read(args.file, kind=kind, spacing=args.spacing, channel=args.channel,
                unit=args.unit)


PART_HELP = ("fit (or check) only this part of the map: left, right, top or "
             "bottom (a half; top: the first rows), or R0:R1,C0:C1 (row and column index "
             "ranges, half-open); the part is recorded in the model file so that 'roughgp "
             "check --held-out' checks the model on the part it did not see")


def add_part_option(parser) -> None:
    """``--part P``: the part of a map to use (:func:`roughgp.checking.held_out.part_of`)."""
    parser.add_argument("--part", metavar="P", help=PART_HELP)


def crop_to_part(args, heights):
    """``heights`` cut to ``--part`` (unchanged without it), and the part (or None). A part
    outside the map or too small is a :class:`UsageError` naming the allowed forms."""
    import dataclasses

    from roughgp.checking.held_out import part_of
    spec = getattr(args, "part", None)
    if spec is None:
        return heights, None
    if heights.kind != "surface":
        raise UsageError(f"--part cuts a surface; {args.file} holds a profile")
    try:
        part = part_of(heights.z.shape, spec)
    except ValueError as error:
        raise UsageError(f"--{error}") from None
    return dataclasses.replace(heights, z=part.cut(heights.z)), part


class Given(argparse.Action):
    """Store the value, and record the option in ``namespace.given`` (the options typed, as
    against defaults: ``--unfiltered`` refuses an operator option that was given)."""

    def __call__(self, parser, namespace, values, option_string=None):
        setattr(namespace, self.dest, values)
        namespace.given = (*getattr(namespace, "given", ()), option_string)


def check_cutoffs(operators: dict, shape, spacing) -> None:
    """:func:`roughgp.batch.steps.check_cutoffs` (the filters' nesting indices against the field
    that was read), its refusal a :class:`UsageError`."""
    from roughgp.batch.steps import check_cutoffs as within_field
    try:
        within_field(operators, shape, spacing)
    except ValueError as error:
        raise UsageError(str(error)) from None


def load_model(path, option="MODEL"):
    """A model file (:class:`roughgp.surface_models.model.FittedModel`); a usage error says
    what is wrong with it."""
    from roughgp.surface_models.model import FittedModel, ModelFileError
    try:
        model = FittedModel.load(path)
    except FileNotFoundError:
        raise UsageError(f"{option}: no such model file: {path}") from None
    except IsADirectoryError:
        raise UsageError(f"{option}: {path} is a directory, not a model file") from None
    except PermissionError:
        raise UsageError(f"{option}: {path} cannot be read (permission denied)") from None
    except (OSError, RuntimeError) as exc:  # a symbolic link loop (RuntimeError in pathlib)
        why = getattr(exc, "strerror", None) or str(exc)
        raise UsageError(f"{option}: cannot read the model file {path}: {why}") from None
    except ModelFileError as exc:
        raise UsageError(f"{option}: {exc}") from None
    if model.marginal_method == "iaaft" and "order_scores" not in model.marginal:
        err(f"note: {option} {path}: its IAAFT heights are keyed at the Hazen positions of "
            f"independent points (a file written before 2026-12-07): its draws' extremes and "
            f"Sq fall short of the measured; fit it again to key them at the model's own order "
            f"statistics (roughgp.surface_models.order_scores)")
    return model


def fitted_size(model, max_points: int) -> list | None:
    """``[NY, NX]`` (a profile: ``[1, N]``) of the data ``model`` was fitted on, as its file
    records it (``data.shape``); None where it records no single size of at most ``max_points``
    points (a model of several maps, an older or edited file)."""
    shape = model.recorded_shape
    if shape is None or math.prod(shape) > max_points:
        return None
    return [1, *shape] if model.kind == "profile" else list(shape)


def add_l_kind_options(parser) -> None:
    """--robust, --stratified: the L-filter's kind (``args.l_kind``; default the Gaussian)."""
    group = parser.add_mutually_exclusive_group()
    group.add_argument("--robust", dest="l_kind", action="store_const", const="robust",
                       default="gaussian",
                       help="L-filter: the robust Gaussian regression filter (ISO 16610-31 / "
                            "-71, second order, Tukey biweight): its mean line does not follow "
                            "spikes, pits or deep valleys")
    group.add_argument("--stratified", dest="l_kind", action="store_const", const="stratified",
                       help="L-filter: ISO 13565-1's for stratified surfaces (valleys suppressed, "
                            "two Gaussian passes), on which Sk/Spk/Svk (Rk/Rpk/Rvk) are defined; "
                            "e.g. plateau-honed surfaces")


def add_spurious_options(parser) -> None:
    """--spurious, --flagged FILE: find the spurious measured points with the GP and leave them
    out (:func:`remove_spurious`)."""
    parser.add_argument("--spurious", action="store_true",
                        help="find spurious measured points (spikes, pits) of the whole "
                             "FILE (--part or not) by the GP's "
                             "leave-one-out scores under a fit without them (|score| > 3.89: "
                             "1e-4 of a clean surface's points; the noise variance scored with "
                             "is at least a robust estimate from the heights' second "
                             "differences) and treat them as unmeasured; prints how many and "
                             "where (default: no point is removed)")
    parser.add_argument("--flagged", metavar="FILE",
                        help="with --spurious: write the map of flagged points (1 flagged, 0 "
                             "not; .npy, .csv or .x3p)")


def flagged_output(args) -> tuple:
    """The ``--flagged`` output, ``(option, path text or None, kind)``, for the command's one
    :func:`roughgp.cli.output.check_outputs` call (checked with its other outputs, against
    every input, before any work); a usage error for --flagged without --spurious."""
    flagged = getattr(args, "flagged", None)
    if flagged and not args.spurious:
        raise UsageError("--flagged writes the points --spurious flags: give --spurious too")
    return ("--flagged", flagged, "heights")


def remove_spurious(args, heights, form="plane", *, file=None, seed=None):
    """With --spurious: the heights of ``heights`` (a Measurement) with the spurious points set
    to NaN (:func:`roughgp.filling.spurious.detect_spurious`, after the F-operator
    ``form``) and the detection (for :func:`write_flagged`, once every other check has
    passed), the summary printed; else the heights as read and None. ``file`` and ``seed``:
    the file named in messages and the detection's seed (default ``args.file`` and
    ``args.seed``; ``simulate --fitted`` gives its map and the fit's seed)."""
    if not args.spurious:
        return heights.z, None
    from roughgp.filling.spurious import detect_spurious
    file = args.file if file is None else file
    seed = getattr(args, "seed", 0) if seed is None else seed
    if heights.z.ndim != 2:
        raise UsageError(f"--spurious: {file} holds a profile; the detection works on "
                         f"surfaces z[iy, ix]")
    from roughgp.cli.pace import Pace
    pace = Pace("--spurious rounds (at most; each fits the map and scores every point)",
                "a smaller map or crop would")
    try:
        found = detect_spurious(heights.z, spacing=heights.spacing, form=form, seed=seed,
                                progress=pace)
    except ValueError as exc:
        raise UsageError(f"--spurious: {file}: {exc}") from None
    removed = "removed (treated as unmeasured)" if found.count else "nothing removed"
    rounds = (f"{found.rounds} rounds" if found.converged else
              f"stopped at the cap of {found.rounds} rounds, the flagged set still growing")
    err(f"--spurious: {found.summary()}; {removed} ({rounds}, {found.seconds:.1f} s)")
    return np.where(found.flagged, np.nan, heights.z), found


def write_flagged(path, found, args, heights) -> None:
    """Write the map of the points ``found`` flagged (:func:`remove_spurious`) to ``path``
    (checked by :func:`flagged_output`), with the command's other outputs: after every check
    and computation, so that a refusal leaves no file behind. Nothing when ``path`` is
    None."""
    if path is None or found is None:
        return
    from roughgp.io.writers import write_heights
    dy, dx = heights.spacing
    write_heights(path, found.flagged.astype(np.float64), dx if dy == dx else (dy, dx),
                  f"roughgp --spurious {args.file}: 1 where a measured point was flagged "
                  f"spurious (|GP leave-one-out score| > {found.threshold:.3g}), 0 elsewhere")
    err(f"wrote {path} (the map of the {found.count} flagged points)")
