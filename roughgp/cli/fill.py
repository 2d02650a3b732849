"""``roughgp fill FILE``: the unmeasured (NaN) points of a surface filled by the GP
(:func:`roughgp.fill`: :func:`roughgp.filling.measured.fill_measured_surface`). Argument
handling and messages only.
"""

from __future__ import annotations

import time
from pathlib import Path

import numpy as np

from roughgp.cli.bounds import bounds_text, check_block, integer
from roughgp.cli.options import (
    add_form_options,
    add_spurious_options,
    flagged_output,
    read_input,
    remove_spurious,
    write_flagged,
)
from roughgp.cli.output import (
    UsageError,
    add_force_option,
    check_device,
    check_outputs,
    describe_groove,
    err,
)
from roughgp.io.writers import WRITE_FORMATS, write_heights

__all__ = ['add_parser', 'run']


_FILL = """\
Fill the unmeasured (NaN) points of a surface, e.g. the non-measured points an optical
instrument leaves at steep flanks: the form is removed (F-operator: a least-squares plane by
default, --form cylinder for a curved part), eq 18 plus white noise is fitted to the
measured points alone (block composite likelihood, roughgp.inference.block_fit) unless
--model gives a model file of 'roughgp fit ground', the missing points get the GP posterior
mean, and the form is added back. Before the fill, 2 % of the measured points (at most
5000) are held out in small discs, filled without them and compared with their heights and
with linear interpolation (roughgp.filling.self_check): the self-check says
whether the GP beats linear interpolation on this file. The 95 % band of --band is then
calibrated on held-out copies of the map's own holes, with one factor per size of hole and
depth in it (roughgp.filling.hole_band); the command says up to which hole size it is
calibrated, and widens it in larger holes; --nu auto fits 0.5, 1.5 and 2.5 and keeps the
smoothness that fills the held-out points best (eq 18 unless another is better by more than
one standard error); --no-check skips both. --method local (default: moving-window kriging,
roughgp.filling.local_fill; bounded work, an exact sd per window, holds on real
measurements) or global (all measured points: conjugate gradients with FFT products and
--samples pathwise draws for the sd; for well-conditioned synthetic cases). --sd also
writes the posterior standard deviation at the filled points. Heights and lengths in um.

example:
  roughgp fill measured.x3p --out filled.x3p --sd sd.x3p --band band.x3p --nu auto --seed 0"""


def add_parser(sub, formatter, input_epilog, add_input_options) -> None:
    """Add ``fill`` to the sub-command parsers ``sub``."""
    f = sub.add_parser("fill", formatter_class=formatter, description=_FILL, epilog=input_epilog,
                       help="fill the missing (NaN) points of a surface with the GP")
    add_input_options(f, kind=False, what="the surface, heights in um, NaN where missing")
    f.add_argument("--out", required=True, metavar="FILE",
                   help="the filled surface: " + ", ".join(WRITE_FORMATS))
    f.add_argument("--sd", metavar="FILE", help="also write the posterior sd map")
    f.add_argument("--band", metavar="FILE",
                   help="also write the half-width of the 95 %% band of a new measurement at "
                        "the filled points (calibrated per size of hole and depth on held-out "
                        "copies of the map's holes; Gaussian 1.96 sd with --no-check)")
    f.add_argument("--model", metavar="MODEL.json",
                   help="use this surface model file (roughgp fit ground: eq 18, Matern, or "
                        "the measured PSD, whose ACVF is the inverse DFT of its PSD) instead "
                        "of a fit")
    add_form_options(f, "F-operator removed and added back")
    add_spurious_options(f)
    f.add_argument("--nu", choices=("0.5", "1.5", "2.5", "auto"), default="0.5",
                   help="smoothness of the fitted kernel: 0.5 is eq 18 (default); 1.5, 2.5 "
                        "a smoother Matern profile; auto: the one the self-check fills best "
                        "(not with --model)")
    f.add_argument("--no-check", dest="check", action="store_false",
                   help="skip the self-check on held-out measured points")
    f.add_argument("--method", choices=("local", "global"), default="local",
                   help="local (default): moving-window kriging; global: all points by CG")
    f.add_argument("--samples", type=integer("--samples"), default=16, metavar="N",
                   help=f"--method global: pathwise draws for --sd, "
                        f"{bounds_text('--samples')} (default 16)")
    f.add_argument("--seed", type=integer("--seed"), default=0, metavar="S",
                   help=f"seed of the blocks chosen for the fit and of the draws, "
                        f"{bounds_text('--seed')} (default 0)")
    add_force_option(f)
    f.add_argument("--block", type=integer("--block"), default=24, metavar="B",
                   help=f"side of the fit's blocks in points, {bounds_text('--block')} "
                        f"(default 24)")
    f.add_argument("--blocks", type=integer("--blocks"), default=12, metavar="K",
                   help=f"blocks used by the fit, {bounds_text('--blocks')} (default 12)")
    f.add_argument("--device", metavar="DEV",
                   help="--method global: run the FFTs and CG through torch on DEV (cpu, "
                        "cuda, cuda:N)")
    f.set_defaults(func=run)


def run(args) -> int:
    """``roughgp fill FILE``: fill the unmeasured points of a surface with the GP posterior."""
    from roughgp.api import fill
    from roughgp.cli.options import load_model
    from roughgp.cli.pace import Pace
    out, sd_out, band_out, flagged_out = check_outputs(
        ("--out", args.out, "heights"), ("--sd", args.sd, "heights"),
        ("--band", args.band, "heights"), flagged_output(args),
        inputs=(("FILE", args.file), ("--model", args.model)), force=args.force)
    nu = args.nu if args.nu == "auto" else float(args.nu)
    if nu == "auto" and args.model:
        raise UsageError("--nu auto chooses the smoothness of a fit; --model has its own "
                         "(leave out one of them)")
    if nu == "auto" and not args.check:
        raise UsageError("--nu auto chooses by the self-check; it cannot run with --no-check")
    model = load_model(args.model, "--model") if args.model else None
    if model is not None and model.kind != "surface":
        raise UsageError(f"--model {args.model} is a {model.kind} model ({model.equation}); "
                         f"fill needs a surface model (roughgp fit ground)")
    check_device(args.device)
    heights = read_input(args, "surface")
    for note in heights.notes:
        err(f"note: {args.file}: {note}")
    if heights.kind != "surface":
        raise UsageError(f"{args.file} holds a profile; fill needs a surface z[iy, ix]")
    (dy, dx) = heights.spacing
    spacing = dx if dy == dx else (dy, dx)
    if dy != dx and ".csv" in {f.suffix.lower() for f in (out, sd_out, band_out, flagged_out)
                               if f}:
        raise UsageError(f"the spacing differs along y and x ({dy:g}, {dx:g} um): a .csv "
                         f"stores one spacing; write .x3p or .npy")
    z, found = remove_spurious(args, heights, None if args.form == "none" else args.form)
    missing = np.isnan(z)
    if not missing.any():
        raise UsageError(f"{args.file} has no missing (NaN) point: nothing to fill")
    if model is None:
        check_block(args.file, args.block, z.shape)
    err(f"{args.file}: {z.shape[0]} x {z.shape[1]} points, spacing {dy:g} x {dx:g} um "
        f"({heights.spacing_source}), {missing.sum()} missing ({missing.mean():.1%})")
    start = time.perf_counter()
    samples = args.samples if (sd_out is not None and args.method == "global") else 0
    try:
        result = fill(z, heights.spacing, model=model, n_samples=samples, seed=args.seed,
                      block=args.block, n_blocks=args.blocks,
                      form=None if args.form == "none" else args.form, degree=args.degree,
                      axis=args.axis, method=args.method, nu=nu, self_check=args.check,
                      device=args.device, progress=Pace("windows of the fill", None))
    except ValueError as exc:
        raise UsageError(f"{args.file}: {exc}") from None
    fit, fill = result.fit, result.gaps
    if args.check and result.self_check is None:
        err(f"note: too few measured points ({(~missing).sum()}) for the self-check; the band "
            f"is the Gaussian one")
    if args.spurious and result.self_checks:
        err("note: the self-check holds out and scores only measured points not flagged spurious")
    for smoothness, check in result.self_checks.items():
        chosen = " <- used" if len(result.self_checks) > 1 and smoothness == result.nu else ""
        err(f"self-check: {check.summary()}{chosen}")
    if result.self_check is not None and result.self_check.verdict == "linear":
        tried = [] if args.spurious else ["--spurious flags spikes and pits"]
        tried += [] if args.nu == "auto" or args.model else ["--nu auto tries smoother kernels"]
        tried += ["another --form removes another form"]
        err(f"note: linear interpolation filled the held-out points better than the GP: the "
            f"model misses something of this surface (spikes, steps, a form left in); "
            f"{'; '.join(tried)}. The band is calibrated on the GP's own errors all the "
            f"same")
    if result.hole_band is not None:
        err(f"self-check: the {result.hole_band.summary(float(min(dy, dx)))}")
    if fit is not None:
        fit_seconds = (time.perf_counter() - start - fill.seconds
                       - (result.hole_band.seconds if result.hole_band is not None else 0.0))
        name = "eq 18" if result.nu == 0.5 else f"eq 18 with Matern nu {result.nu:g}"
        used = (f"{name} plus white noise fitted to the measured points "
                f"({describe_groove(fit.groove)}, noise variance {fit.noise_variance:.4g} um^2)")
        how = " and self-checked" if result.self_checks else ""
        err(f"{name} fitted{how} on {fit.n_points} measured points of {len(fit.blocks)} blocks "
            f"in {fit_seconds:.1f} s: {describe_groove(fit.groove)}, noise variance "
            f"{fit.noise_variance:.4g} um^2" + (" (without the held-out points)"
                                                 if result.self_checks else ""))
    else:
        used = f"the model {Path(args.model).name} ({model.describe()})"
        err(f"model {args.model}: {model.describe()}")
    if args.method == "global":
        if not fill.converged:
            err("warning: conjugate gradients did not reach their tolerance; the fill is "
                "approximate (try --method local)")
        if fill.prior_clipped_fraction > 0:
            err(f"note: the sd's prior draws come from a clipped circulant embedding: "
                f"{fill.prior_clipped_fraction:.2g} of the prior variance lost")
        err(f"filled in {fill.seconds:.1f} s ({fill.iterations} CG iterations"
            + (f", {samples} draws for the sd" if samples else "") + ")")
    else:
        err(f"filled in {fill.seconds:.1f} s (moving-window kriging: {fill.tiles} windows, at "
            f"most {fill.largest_window} measured points each)")
    comment = (f"roughgp fill {Path(args.file).name} --seed {args.seed}: the form "
               f"({result.form.label}) removed and added back, {used}, the {missing.sum()} "
               f"missing points filled by the GP posterior mean ({args.method})")
    write_heights(out, result.filled, spacing, comment, source=heights.meta)
    err(f"wrote {out} (the measured heights, the {missing.sum()} missing ones filled by the "
        f"posterior mean)")
    if sd_out is not None:
        write_heights(sd_out, result.sd, spacing,
                      comment + "; this file: the posterior sd"
                      + (f" ({samples} draws)" if args.method == "global" else ""),
                      source=heights.meta, spread=True)
        sd = result.sd[missing]
        err(f"wrote {sd_out} (posterior sd of the latent surface at the filled points, 0 at "
            f"measured ones; median {np.median(sd):.3g} um, largest {sd.max():.3g} um)")
    if band_out is not None:
        factors = result.band_factors[missing]
        if result.hole_band is not None and result.hole_band.calibrated_classes:
            how = (f"{factors.min():.3g} to {factors.max():.3g} predictive sd, by size of hole "
                   f"and depth and the roughness around the hole, calibrated for holes up to "
                   f"{result.hole_band.calibrated_width:.0f} points across")
        elif result.hole_band is not None:
            how = (f"{factors.min():.3g} to {factors.max():.3g} predictive sd: the untested, "
                   f"widened factor times the roughness around each hole, no hole size "
                   f"calibrated on this map")
        else:
            how = f"{result.band_factor:.3g} predictive sd (Gaussian, no self-check)"
        write_heights(band_out, result.band, spacing,
                      comment + f"; this file: the half-width of the 95 % band of a new "
                      f"measurement, {how}", source=heights.meta, spread=True)
        err(f"wrote {band_out} (the 95 % band's half-width at the filled points: {how}; 0 at "
            f"measured ones)")
    write_flagged(flagged_out, found, args, heights)
    return 0
