"""Options that several commands share: the F-, S- and L-operators (texture, fit) and a
model file (simulate, check, fill). Argument handling only.
"""

from __future__ import annotations

import argparse
import math

import numpy as np

from roughgp.cli.output import UsageError
from roughgp.common.checks import check_scale

__all__ = ["cutoff", "add_form_options", "add_operator_options", "operator_settings",
           "load_model", "check_scales", "add_l_kind_options", "add_spurious_options",
           "remove_spurious"]


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
                        default="plane", help=f"{what} (default plane: a line for a profile)")
    parser.add_argument("--degree", type=int, default=2, metavar="N",
                        help="degree of --form polynomial (default 2)")
    parser.add_argument("--axis", choices=("auto", "x", "y"), default="auto",
                        help="the axis of --form cylinder (default auto: the better fit)")


def add_operator_options(parser, *, s_default="auto", l_default="auto") -> None:
    """--form, --degree, --axis, --s-filter, --l-filter."""
    add_form_options(parser)
    parser.add_argument("--s-filter", type=cutoff, default=s_default, metavar="S",
                        help=f"S-filter nesting index in um, auto or none (default {s_default})")
    parser.add_argument("--l-filter", type=cutoff, default=l_default, metavar="L",
                        help=f"L-filter nesting index (cut-off) in um, auto or none (default "
                             f"{l_default})")


def operator_settings(args) -> dict:
    """``form``, ``s``, ``l``, ``degree``, ``axis`` for the library from the options."""
    if args.degree < 1:
        raise UsageError(f"--degree must be >= 1, got {args.degree}")

    def length(value):
        return None if value == "none" else value

    return {"form": None if args.form == "none" else args.form, "s": length(args.s_filter),
            "l": length(args.l_filter), "degree": args.degree, "axis": args.axis}


def load_model(path, option="MODEL"):
    """A model file (:class:`roughgp.beyond.measured.model.FittedModel`); a usage error says
    what is wrong with it."""
    from roughgp.beyond.measured.model import FittedModel, ModelFileError
    try:
        return FittedModel.load(path)
    except FileNotFoundError:
        raise UsageError(f"{option}: no such model file: {path}") from None
    except ModelFileError as exc:
        raise UsageError(f"{option}: {exc}") from None


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
                        help="find spurious measured points (spikes, pits) by the GP's "
                             "leave-one-out scores under a fit without them (|score| > 3.89: "
                             "1e-4 of a clean surface's points) and treat them as unmeasured; "
                             "prints how many and where (default: no point is removed)")
    parser.add_argument("--flagged", metavar="FILE",
                        help="with --spurious: write the map of flagged points (1 flagged, 0 "
                             "not; .npy, .csv or .x3p)")


def remove_spurious(args, heights, form="plane"):
    """With --spurious: the heights of ``heights`` (a Measurement) with the spurious points set
    to NaN (:func:`roughgp.beyond.measured.spurious.detect_spurious`, after the F-operator
    ``form``), the summary printed and the map written to --flagged (checked first); else the
    heights as read."""
    from roughgp.cli.output import check_outputs, err
    if args.flagged and not args.spurious:
        raise UsageError("--flagged writes the points --spurious flags: give --spurious too")
    if not args.spurious:
        return heights.z
    from roughgp.beyond.measured.spurious import detect_spurious
    from roughgp.metrology.writers import write_heights
    flagged_path = check_outputs(("--flagged", args.flagged, "heights"), inputs=(args.file,),
                                 force=getattr(args, "force", False))[0]
    if heights.z.ndim != 2:
        raise UsageError(f"--spurious: {args.file} holds a profile; the detection works on "
                         f"surfaces z[iy, ix]")
    try:
        found = detect_spurious(heights.z, spacing=heights.spacing, form=form,
                                seed=getattr(args, "seed", 0))
    except ValueError as exc:
        raise UsageError(f"--spurious: {args.file}: {exc}") from None
    removed = "removed (treated as unmeasured)" if found.count else "nothing removed"
    err(f"--spurious: {found.summary()}; {removed} ({found.seconds:.1f} s)")
    if flagged_path is not None:
        dy, dx = heights.spacing
        write_heights(flagged_path, found.flagged.astype(np.float64),
                      dx if dy == dx else (dy, dx),
                      f"roughgp --spurious {args.file}: 1 where a measured point was flagged "
                      f"spurious (|GP leave-one-out score| > {found.threshold:.3g}), 0 elsewhere")
        err(f"wrote {flagged_path} (the map of the {found.count} flagged points)")
    return np.where(found.flagged, np.nan, heights.z)
