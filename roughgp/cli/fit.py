"""``roughgp fit FILE``: the spectral-mixture fit (eq 21) of section 3.3 to a profile, or to
the mean profile of a surface. Argument handling and the printed table only.
"""

from __future__ import annotations

import math
import time
import warnings

import numpy as np

from roughgp.cli.output import (
    UsageError,
    add_force_option,
    check_outputs,
    check_spacing,
    err,
    print_wrapped,
    write_json,
)
from roughgp.metrology.measurement import mean_profile, read_measurement

__all__ = ['add_parser', 'run']


_FIT = """\
Fit the spectral mixture ACVF of eq 21 (Q Gaussian lines plus white noise) to a profile by
maximum marginal likelihood, as in section 3.3: candidates from Welch and periodogram PSD
estimates, the best optimised. The profile is levelled first (least-squares line). A
surface is reduced to its MEAN PROFILE: with --axis x (default) the rows are averaged
(over y, i.e. along the lay of a turned surface whose feed marks run along y), leaving a
profile along x; --axis y averages the columns. Prints and (--out) writes the weights
(um^2), periods 1/mu (um), line widths (the standard deviation of each spectral Gaussian,
1/um), the noise variance, the log marginal likelihood and the dominant period.
The exact likelihood costs O(n^2) per step: a few thousand points take seconds to minutes.

example:
  roughgp fit turned.csv --mixtures 5 --seed 0 --out fit.json"""



def add_parser(sub, formatter, input_epilog, add_input_options) -> None:
    """Add ``fit`` to the sub-command parsers ``sub``."""
    f = sub.add_parser("fit", formatter_class=formatter, description=_FIT, epilog=input_epilog,
                       help="spectral-mixture fit (eq 21) of a profile")
    add_input_options(f)
    f.add_argument("--mixtures", type=int, default=5, metavar="Q",
                   help="number of spectral-mixture components (default 5, the paper's)")
    f.add_argument("--seed", type=int, default=0, metavar="S",
                   help="seed of the fit's initialisations (default 0)")
    f.add_argument("--candidates", type=int, default=10, metavar="N",
                   help="initialisations scored (default 10)")
    f.add_argument("--axis", choices=("x", "y"), default="x",
                   help="for a surface: the direction of the mean profile (default x)")
    f.add_argument("--out", metavar="RESULT.json", help="write the fit as JSON (.json)")
    add_force_option(f)
    f.set_defaults(func=run)


def run(args) -> int:
    """``roughgp fit FILE``: the spectral-mixture fit (eq 21) of section 3.3."""
    from roughgp.inference import fitting
    from roughgp.metrology import levelling
    if args.mixtures < 1:
        raise UsageError(f"--mixtures must be >= 1, got {args.mixtures}")
    if args.candidates < 1:
        raise UsageError(f"--candidates must be >= 1, got {args.candidates}")
    check_spacing(args.spacing)
    check_outputs(("--out", args.out, "json"), inputs=(args.file,), force=args.force)
    heights = read_measurement(args.file, kind=args.kind, spacing=args.spacing,
                               channel=args.channel, unit=args.unit)
    for note in heights.notes:
        err(f"note: {args.file}: {note}")
    z, spacing, how = mean_profile(heights, args.axis)
    missing = int(np.count_nonzero(np.isnan(z)))
    if missing:
        raise UsageError(f"{args.file}: the profile has {missing} missing (NaN) point(s); the "
                         "fit needs a complete profile (fill or crop them first)")
    if z.size < fitting.MIN_POINTS:
        raise UsageError(f"{args.file}: the profile has {z.size} points; the fit needs at "
                         f"least {fitting.MIN_POINTS}")
    z, line = levelling.level(z, spacing=spacing, return_coefficients=True)
    x = np.arange(z.size) * spacing
    if z.size > 16384:
        err(f"note: {z.size} points; the exact likelihood costs O(n^2) per step, so this "
             "can take many minutes (crop or decimate the profile for a quicker look)")
    err(f"fitting Q = {args.mixtures} spectral-mixture components (eq 21) to {z.size} points "
         f"(spacing {spacing:g} um, {how}) ...")
    start = time.perf_counter()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        fit = fitting.fit_spectral_mixture(x, z, args.mixtures, seed=args.seed,
                                           n_candidates=args.candidates,
                                           n_optimise=min(3, args.candidates))
    seconds = time.perf_counter() - start
    try:
        dominant = fit.dominant_component
        period = fit.dominant_period
    except ValueError:
        dominant, period = None, math.nan

    components = []
    for k, (w, mu, v) in enumerate(zip(fit.weights, fit.means, fit.variances)):
        components.append({"weight_um2": float(w), "frequency_per_um": float(mu),
                           "period_um": float(1 / mu) if mu > 0 else math.inf,
                           "line_width_per_um": float(math.sqrt(v)),
                           "variance_per_um2": float(v)})
    print(f"spectral-mixture fit (eq 21), Q = {args.mixtures}, of {args.file}")
    print_wrapped(f"profile: {how}; {z.size} points, spacing {spacing:g} um "
                   f"({heights.spacing_source}); least-squares line removed (slope "
                   f"{line.slope[0]:.3g} um/um)")
    print(f"  {'k':>2}  {'weight (um^2)':>14}  {'period 1/mu (um)':>17}  "
          f"{'line width (1/um)':>18}  {'':8}")
    for k, c in enumerate(components):
        mark = "dominant" if k == dominant else ""
        print(f"  {k:>2}  {c['weight_um2']:>14.5g}  {c['period_um']:>17.5g}  "
              f"{c['line_width_per_um']:>18.4g}  {mark}")
    print(f"  noise variance: {fit.noise_variance:.4g} um^2")
    print(f"  log marginal likelihood: {fit.log_marginal_likelihood:.6g}")
    print(f"  dominant period: {period:.5g} um" + ("" if dominant is not None else
                                                    " (no component's period fits)"))
    print(f"  ({seconds:.1f} s; line width: standard deviation of the spectral Gaussian)")
    if args.out:
        write_json(args.out, {
            "file": str(args.file), "kind": heights.kind, "profile": how,
            "n_points": int(z.size), "spacing_um": float(spacing),
            "spacing_from": heights.spacing_source,
            "levelling": {"offset_um": line.offset, "slope": line.slope[0]},
            "num_mixtures": args.mixtures, "seed": args.seed,
            "components": components, "noise_variance_um2": fit.noise_variance,
            "log_marginal_likelihood": fit.log_marginal_likelihood,
            "dominant_component": dominant, "dominant_period_um": period,
            "seconds": round(seconds, 2)})
    return 0

