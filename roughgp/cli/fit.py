"""``roughgp fit profile|ground FILE``: fit a model to a measurement and write it as a model
file (:mod:`roughgp.surface_models`). Argument handling and the printed table only.
"""

from __future__ import annotations

import argparse
import dataclasses
import math
import time

import numpy as np

from roughgp.cli.bounds import bounds_text, check_block, integer
from roughgp.cli.fit_auto import choose_auto_command
from roughgp.cli.fit_periodic import (
    fit_periodic_command,
    fit_periodic_profile_command,
    note_periodic_mark,
)
from roughgp.cli.fit_regions import (
    fit_field_command,
    fit_population_command,
    fit_population_files_command,
)
from roughgp.cli.options import (
    add_operator_options,
    add_part_option,
    add_spurious_options,
    check_cutoffs,
    crop_to_part,
    flagged_output,
    operator_settings,
    read_input,
    remove_spurious,
    write_flagged,
)
from roughgp.cli.output import (
    UsageError,
    add_force_option,
    check_device,
    check_outputs,
    err,
    print_operators,
    print_wrapped,
    refused_by,
)
from roughgp.io.measurement import mean_profile
from roughgp.io.writers import atomic_output
from roughgp.surface_models.schema import MAX_ANCHORS

__all__ = ['add_parser', 'run', 'MAX_PROFILE_POINTS']

#: the exact eq 21 likelihood costs O(n^2) per step: beyond this it takes hours
MAX_PROFILE_POINTS = 65536

_FIT = """\
Fit a model to a measurement and write it as a model file (--out MODEL.json: versioned JSON
with the equation, the hyperparameters with their units, the operators applied, the data
and the log likelihood) that 'roughgp simulate --from', 'roughgp check' and 'roughgp fill
--model' read.

examples:
  roughgp fit ground land.x3p --form cylinder --l-filter 250 --out land-model.json
  roughgp fit profile turned.csv --mixtures 5 --seed 0 --out profile-model.json"""

_PROFILE = """\
Fit the spectral mixture ACVF of eq 21 (Q Gaussian lines plus white noise) to a profile by
maximum marginal likelihood, as in section 3.3: candidates from Welch and periodogram PSD
estimates, the best optimised, on the heights after the F-operator (a least-squares line by
default); S- and L-filters, when asked, are kept in the model file and applied to its
simulations by 'roughgp check' and 'roughgp simulate --from' as to the measurement. A
surface is reduced to its MEAN PROFILE: with --axis x (default) the rows are averaged (over
y, i.e. along the lay of a turned surface whose feed marks run along y), leaving a profile
along x; --axis y averages the columns.
Prints the weights (um^2), periods 1/mu (um), line widths (the standard deviation of each
spectral Gaussian, 1/um), the noise variance, the log marginal likelihood and the dominant
period. The exact likelihood costs O(n^2) per step: a few thousand points take seconds to
minutes; at most 65536 points.
--model periodic fits a periodic machined profile (turned, milled, shaped) as a deterministic
feed mark plus Gaussian processes instead (roughgp.surface_models.periodic_model): the mark
folded at the feed (found, or --feed F um), each mark's shift and depth random from mark to
mark, eq 18's exponential in one dimension plus noise on the rest; where the profile holds no
mark that repeats (the mark of one half must explain half of the other's variance) it says so
and fits eq 21.

example:
  roughgp fit profile turned.csv --mixtures 5 --seed 0 --out fit.json
  roughgp fit profile turned.csv --model periodic --out marks.json"""

_GROUND = """\
Fit eq 18 (the rotated anisotropic exponential ACVF: variance, lambda_a along the lay,
lambda_b across it, the lay angle) plus white noise (eq 8) to a measured surface, holes
allowed: maximum block composite likelihood on the measured points of --blocks random
windows of --block x --block points (roughgp.inference.block_fit), or with --likelihood
whittle the debiased spatial Whittle likelihood of every measured point
(roughgp.inference.whittle_fit: FFTs, its precision grows with the map; the block fit's does
not: on a 256 x 256 map it leaves the variance and lengths uncertain to about 15 %, the
Whittle fit to 13 % and at 512 x 512 to 7 %, benchmarks/fit_recovery.py). The model describes the
heights after the F-operator (plane by default; --form cylinder for a curved part such as a
bullet land). The S- and L-filters (default: no S-filter, the model's noise stands for the
instrument's; the standard's L-filter, the largest preferred nesting index <= a fifth of the
field) are kept in the model file as the rest of the measurement's chain: 'roughgp check'
and 'roughgp simulate --from' put the simulations through them as the measurement went
(like with like). --non-gaussian keeps the heights' skewness and kurtosis in the model (its
simulations are then Johnson-transformed GPs, roughgp.non_gaussian).

--model chooses the rung of the ladder of models (roughgp.surface_models.ladder):
  eq18    the paper's eq 18 (default; --nu 1.5 or 2.5 makes it the Matern variant);
  matern  eq 18's anisotropy with a Matern profile, nu = --nu if 1.5 or 2.5, else 1.5;
  sm      a 2-D spectral mixture (eq 21/22's family on a surface,
          roughgp.surface_models.spectral_mixture): a broad component plus peaks for a lay, a period
          or harmonics, fitted by the Whittle likelihood of the periodogram, Q <= 4 by BIC;
          for structured or periodic surfaces;
  psd     the measured PSD itself, smoothed (roughgp.surface_models.measured_psd): no
          parametric form, the bound of what any stationary Gaussian model can do on the file;
  field   eq 18 whose variance, lengths and lay vary over the map
          (roughgp.surface_models.field_model): eq 18 fitted on each of --anchors M N tiles
          by the Whittle likelihood, pooled by random effects (a tile keeps its own value
          only as far as its fit is sure of it; a gradient is kept where a test finds one),
          interpolated between the tiles' centres; Gaussian heights; for a surface whose
          roughness or lay changes across the part (not among auto's choices);
  population
          eq 18 over a population of regions (roughgp.surface_models.population_model): from
          several measurements of one part (fit ground A.x3p B.x3p ... --model population,
          each file one region) or the --anchors M N tiles of one map (default 2 2), eq 18
          fitted on each region by the Whittle likelihood and pooled by random effects; each
          simulated surface draws its own region's variance, lengths and lay about the
          population's, so a check of another region of the part compares it with many
          regions; Gaussian heights (not among auto's choices);
  periodic
          a periodic machined surface (turned, milled, shaped, fly-cut) as a deterministic
          feed mark plus Gaussian processes (roughgp.surface_models.periodic_model): the mark
          folded at the feed (found, or --feed F um), each mark's shift and depth random from
          mark to mark and along the lay, eq 18 on the rest by the Whittle likelihood; where
          no direction holds a mark that repeats (the mark of one half of the map must
          explain half of the other's variance) it says so and falls back to auto;
  auto    fits the four without 2 % of the measured points (held out in small discs),
          predicts those by kriging with each model's covariance, prints one line per model
          (held-out RMSE, seconds) and keeps the simplest within one standard error of the
          best; then chooses its heights' distribution by the out-of-sample check
          (roughgp.checking.auto_choice): the chosen model fitted with each of gaussian,
          johnson and iaaft heights on one half of the map's central window (at most 512 x
          256 points), checked with 19 simulations on the other half, the one with the
          fewest texture parameters outside kept (a --marginal given is kept, its count
          printed); the chosen one is fitted again on all points.
--marginal gaussian|johnson|iaaft: the heights' distribution (default gaussian; with --model
auto, chosen); johnson: their skewness and kurtosis, the same as --non-gaussian; iaaft: their
whole distribution, 1001 quantiles, matched exactly by iterated amplitude-adjusted Fourier
transforms, roughgp.surface_models.iaaft.

examples:
  roughgp fit ground land.x3p --form cylinder --out land-model.json
  roughgp fit ground map.x3p --model auto --marginal iaaft --out map-model.json
  roughgp fit ground a.x3p b.x3p c.x3p d.x3p --model population --out part-model.json"""


def add_parser(sub, formatter, input_epilog, add_input_options) -> None:
    """Add ``fit`` and its models to the sub-command parsers ``sub``."""
    f = sub.add_parser("fit", formatter_class=formatter, description=_FIT,
                       help="fit eq 21 to a profile or eq 18 to a surface; write a model file")
    models = f.add_subparsers(dest="model", metavar="MODEL", required=True,
                              title="models (roughgp fit MODEL --help for each)")
    shared = argparse.ArgumentParser(add_help=False)
    shared.add_argument("--seed", type=integer("--seed"), default=0, metavar="S",
                        help=f"seed of the fit's initialisations or blocks, "
                             f"{bounds_text('--seed')} (default 0)")
    shared.add_argument("--non-gaussian", action="store_true",
                        help="keep the heights' skewness and kurtosis in the model")
    shared.add_argument("--out", metavar="MODEL.json", help="write the model file (.json)")

    p = models.add_parser("profile", parents=[shared], formatter_class=formatter,
                          description=_PROFILE, epilog=input_epilog,
                          help="eq 21 spectral mixture of a profile (section 3.3)")
    add_input_options(p)
    add_operator_options(p, s_default="none", l_default="none")
    p.add_argument("--mixtures", type=integer("--mixtures"), default=5, metavar="Q",
                   help=f"spectral-mixture components, {bounds_text('--mixtures')} (default "
                        f"5, the paper's)")
    p.add_argument("--candidates", type=integer("--candidates"), default=10, metavar="N",
                   help=f"initialisations scored, {bounds_text('--candidates')} (default 10)")
    p.add_argument("--profile-axis", choices=("x", "y"), default="x",
                   help="for a surface: the direction of the mean profile (default x)")
    p.add_argument("--model", dest="rung", choices=("eq21", "periodic"), default="eq21",
                   help="the model: eq21 (default, the paper's) or periodic (a feed mark plus "
                        "GPs; see above)")
    p.add_argument("--feed", type=float, default=None, metavar="F",
                   help=f"--model periodic: the feed in um when known, "
                        f"{bounds_text('--feed')} and at most a quarter of the profile "
                        f"(default: found from the data)")
    add_force_option(p)
    p.set_defaults(func=run)

    g = models.add_parser("ground", parents=[shared], formatter_class=formatter,
                          description=_GROUND, epilog=input_epilog,
                          help="eq 18 + noise on a measured surface with holes")
    add_input_options(g, kind=False, what="the surface, heights in um, NaN where missing")
    g.add_argument("more", nargs="*", metavar="FILE2",
                   help="--model population: further measurements of the same part, of the "
                        "same spacing (each one region)")
    add_operator_options(g, s_default="none", l_default="auto")
    add_spurious_options(g)
    add_part_option(g)
    g.add_argument("--nu", type=float, choices=(0.5, 1.5, 2.5), default=0.5,
                   help="smoothness: 0.5 is eq 18 (default); 1.5 or 2.5 its anisotropy with a "
                        "smoother Matern profile, for smooth surfaces (beyond the paper)")
    g.add_argument("--model", dest="rung",
                   choices=("eq18", "matern", "sm", "psd", "field", "population", "periodic",
                            "auto"),
                   default="eq18", help="the model: eq18 (default), matern, sm (a 2-D spectral "
                   "mixture of up to 4 components, Q by BIC, for lays and periods), psd (the "
                   "measured PSD), field, population (regions drawn from a population), "
                   "periodic (a feed mark plus GPs) or auto (chosen by a held-out score; see "
                   "above)")
    g.add_argument("--feed", type=float, default=None, metavar="F",
                   help=f"--model periodic: the feed in um when known, "
                        f"{bounds_text('--feed')} and at most a quarter of the map (default: "
                        f"found from the data)")
    g.add_argument("--marginal", choices=("gaussian", "johnson", "iaaft"), default=None,
                   help="the heights' distribution (default gaussian; --model auto: chosen "
                        "by the out-of-sample check; --non-gaussian is johnson)")
    g.add_argument("--likelihood", choices=("blocks", "whittle"), default="blocks",
                   help="eq 18's (and the Matern rung's) likelihood: blocks (default: --blocks "
                        "random blocks of --block x --block points) or whittle (the debiased "
                        "spatial Whittle likelihood of every measured point: its precision "
                        "grows with the map)")
    g.add_argument("--anchors", type=integer("--anchors"), nargs=2, default=None, metavar=("M", "N"),
                   help="--model field: the fields' anchors, the centres of M x N tiles of "
                        "at least 16 x 16 points, M and N in [1, 32] (default 4 4); --model "
                        "population of one map: its M x N tiles are the regions (default 2 2)")
    g.add_argument("--device", metavar="DEV",
                   help="--likelihood whittle or --model field or population: compute the "
                        "Whittle fits' FFTs and gradients through torch on DEV (cpu, cuda, "
                        "cuda:N)")
    g.add_argument("--block", type=integer("--block"), default=24, metavar="B",
                   help=f"side of the fit's blocks in points, {bounds_text('--block')} "
                        f"(default 24)")
    g.add_argument("--blocks", type=integer("--blocks"), default=12, metavar="K",
                   help=f"blocks used by the fit, {bounds_text('--blocks')} (default 12)")
    add_force_option(g)
    g.set_defaults(func=run)


def run(args) -> int:
    """``roughgp fit MODEL FILE``."""
    _check_fit_device(args)
    operators = operator_settings(args)
    more = tuple(getattr(args, "more", None) or ())
    out, flagged_out = check_outputs(("--out", args.out, "json"), flagged_output(args),
                                     inputs=(("FILE", args.file),
                                             *(("FILE2", f) for f in more)),
                                     force=args.force)
    heights = read_input(args, getattr(args, "kind", "surface"))
    full_shape = heights.z.shape
    whole = heights
    heights, part = crop_to_part(args, heights)
    check_cutoffs(operators, heights.z.shape, heights.spacing)
    found = None
    if args.model != "profile" and not more:
        if heights.kind != "surface":
            raise UsageError(f"{args.file} holds a profile; fit ground needs a surface "
                             f"z[iy, ix] (fit a profile with: roughgp fit profile)")
        check_block(args.file, args.block, heights.z.shape)
        # found on the whole file, --part or not: a point's verdict depends on the file alone,
        # and the fit and `check --held-out` leave out the same points
        z, found = remove_spurious(args, whole, operators["form"])
        heights = dataclasses.replace(heights, z=z if part is None else part.cut(z))
    for note in heights.notes:
        err(f"note: {args.file}: {note}")
    from roughgp.io.provenance import of_file
    data = of_file(args.file, heights)
    if part is not None:
        data["part"] = part.to_dict()
        err(f"fitting the part {part.name} of {args.file}: rows {part.rows[0]}:{part.rows[1]}, "
            f"columns {part.cols[0]}:{part.cols[1]} of {full_shape[0]} x {full_shape[1]}")
    start = time.perf_counter()
    if args.model == "profile":
        model = _fit_profile(args, heights, operators, data)
    elif more:
        model = fit_population_files_command(args, heights, operators, data, more)
    else:
        model = _fit_ground(args, heights, operators, data)
    err(f"({time.perf_counter() - start:.1f} s)")
    if out is not None:
        with atomic_output(out) as partial:  # whole or not at all; missing folders made
            model.save(partial)
        err(f"wrote {out} (roughgp model file; roughgp simulate --from {out.name} ...)")
    write_flagged(flagged_out, found, args, whole)
    return 0


def _check_fit_device(args) -> None:
    """``--device`` is for eq 18's Whittle fit alone (the block fit and the other rungs have no
    device path): refused elsewhere, and a device this machine lacks refused, before any
    work."""
    if args.model == "profile":
        if args.feed is not None and args.rung != "periodic":
            raise UsageError("--feed applies to --model periodic only (got --model eq21)")
        if args.rung == "periodic" and args.non_gaussian:
            raise UsageError("--model periodic draws Gaussian roughness on its marks: leave out "
                             "--non-gaussian")
        return
    device = getattr(args, "device", None)
    anchors = getattr(args, "anchors", None)
    if anchors is not None:
        if args.rung not in ("field", "population"):
            raise UsageError(f"--anchors applies to --model field and population only (got "
                             f"--model {args.rung})")
        if not all(1 <= a <= MAX_ANCHORS for a in anchors):
            raise UsageError(f"--anchors must be two integers in [1, {MAX_ANCHORS}], got "
                             f"{anchors[0]} {anchors[1]}")
    more = getattr(args, "more", None) or ()
    if more and args.rung != "population":
        raise UsageError(f"several files ({1 + len(more)}) are for --model population (the "
                         f"measurements of one part, each a region); --model {args.rung} "
                         f"fits one FILE")
    if more and (args.part is not None or args.spurious):
        raise UsageError(f"--model population of several files fits each file whole: leave "
                         f"out {'--part' if args.part is not None else '--spurious'}")
    if anchors is not None and more:
        raise UsageError("--anchors sets the tiles of one map; with several files each file is "
                         "one region: leave out --anchors")
    if getattr(args, "feed", None) is not None and args.rung != "periodic":
        raise UsageError(f"--feed applies to --model periodic only (got --model {args.rung})")
    if getattr(args, "rung", None) in ("field", "population", "periodic"):
        marginal = _marginal_choice(args)
        if marginal != "gaussian" or args.nu != 0.5:
            raise UsageError(f"--model {args.rung} draws Gaussian heights with eq 18's profile: "
                             f"leave out --marginal {marginal} / --non-gaussian and --nu "
                             f"{args.nu:g}")
    if device is None:
        return
    if args.rung in ("field", "population", "periodic") or (args.rung == "eq18"
                                             and args.likelihood == "whittle"):
        check_device(device)
        return
    raise UsageError(f"--device applies to --model eq18 with --likelihood whittle and to "
                     f"--model field or periodic only (got --model {args.rung}, --likelihood "
                     f"{args.likelihood}); leave --device out or add --likelihood whittle")


def _fit_profile(args, heights, operators, data):
    from roughgp.surface_models.fit import fit_profile_model
    z, spacing, how = mean_profile(heights, args.profile_axis)
    holes = int(np.count_nonzero(np.isnan(z)))
    if holes:
        fix = ("fill the surface first (roughgp fill FILE --out FILLED.x3p) or crop it"
               if heights.kind == "surface" else "crop it to a complete stretch (roughgp fill "
               "fills surfaces only)")
        fitted = "eq 21" if args.rung == "eq21" else "periodic-mark"
        raise UsageError(f"{args.file}: {how}: {holes} of {z.size} points unmeasured (NaN); the "
                         f"{fitted} fit needs a complete profile: {fix}")
    if args.rung == "periodic":
        model = fit_periodic_profile_command(args, z, spacing, how, heights, operators, data)
        if model is not None:
            return model
    if z.size > MAX_PROFILE_POINTS:
        raise UsageError(f"{args.file}: the profile has {z.size} points; the exact eq 21 fit "
                         f"costs O(n^2) per step and takes at most {MAX_PROFILE_POINTS} points "
                         f"(crop or decimate it)")
    err(f"fitting Q = {args.mixtures} spectral-mixture components (eq 21) to {z.size} points "
        f"(spacing {spacing:g} um, {how}) ...")
    result = fit_profile_model(z, spacing, form=operators["form"], s=operators["s"],
                               l=operators["l"], num_mixtures=args.mixtures, seed=args.seed,
                               n_candidates=args.candidates, non_gaussian=args.non_gaussian,
                               data={**data, "profile": how})
    fit, model = result.mixture, result.model
    try:
        dominant, period = fit.dominant_component, fit.dominant_period
    except ValueError:
        dominant, period = None, math.nan
    print(f"spectral-mixture fit (eq 21), Q = {args.mixtures}, of {args.file}")
    print_wrapped(f"profile: {how}; {z.size} points, spacing {spacing:g} um "
                  f"({heights.spacing_source}); operators: {'; '.join(model.operators)}")
    print(f"  {'k':>2}  {'weight (um^2)':>14}  {'period 1/mu (um)':>17}  "
          f"{'line width (1/um)':>18}  {'':8}")
    for k, (w, mu, v) in enumerate(zip(fit.weights, fit.means, fit.variances)):
        mark = "dominant" if k == dominant else ""
        p = 1 / mu if mu > 0 else math.inf
        print(f"  {k:>2}  {w:>14.5g}  {p:>17.5g}  {math.sqrt(v):>18.4g}  {mark}")
    print(f"  noise variance: {fit.noise_variance:.4g} um^2")
    print(f"  log marginal likelihood: {fit.log_marginal_likelihood:.6g}")
    print(f"  dominant period: {period:.5g} um" + ("" if dominant is not None else
                                                    " (no component's period fits)"))
    _print_marginal(model)
    return model


def _marginal_choice(args):
    if args.marginal is not None and args.non_gaussian and args.marginal != "johnson":
        raise UsageError(f"--non-gaussian is --marginal johnson; it cannot be combined with "
                         f"--marginal {args.marginal}")
    return args.marginal or ("johnson" if args.non_gaussian else "gaussian")


def _fit_rungs(args, heights, operators, data, z):
    """``fit ground --model matern|sm|psd|auto``: the ladder (roughgp.surface_models.ladder)."""
    from roughgp.surface_models.ladder import fit_rung
    marginal = _marginal_choice(args)
    nu = args.nu if args.nu in (1.5, 2.5) else 1.5
    settings = dict(**operators, marginal=marginal, seed=args.seed, block=args.block,
                    n_blocks=args.blocks, nu=nu, data=data, likelihood=args.likelihood)
    if args.rung == "auto":
        note_periodic_mark(args, heights, operators, z)
        model, notes = choose_auto_command(args, heights, z, settings)
    else:
        with refused_by(args.file):
            model, notes = fit_rung(args.rung, z, heights.spacing, **settings)
    print(f"fitted to {args.file}: {model.describe()}")
    print_operators(model)
    if model.equation == "sm2d":
        _print_mixture(model)
    for note in notes:
        print_wrapped(f"note: {note}")
    _print_marginal(model)
    return model


def _print_mixture(model):
    """The 2-D spectral mixture's components, one line each, and the BIC of each Q tried."""
    hp = model.hyperparameters
    print(f"  {'k':>2}  {'weight (um^2)':>14}  {'period (um)':>12}  {'wave dir (deg)':>14}  "
          f"{'bandwidths a, b (1/um)':>23}  {'axes (deg)':>10}")
    for k, (w, fx, fy, a, b, angle) in enumerate(zip(
            hp["weights_um2"], hp["frequencies_x_per_um"], hp["frequencies_y_per_um"],
            hp["bandwidths_a_per_um"], hp["bandwidths_b_per_um"], hp["axes_deg"]), start=1):
        f = math.hypot(fx, fy)
        period = f"{1 / f:.5g}" if f > max(a, b) else "(no peak)"
        direction = f"{math.degrees(math.atan2(fy, fx)) % 180:.1f}" if f > max(a, b) else ""
        print(f"  {k:>2}  {w:>14.5g}  {period:>12}  {direction:>14}  "
              f"{f'{a:.4g}, {b:.4g}':>23}  {angle % 180:>10.1f}")
    print(f"  noise variance: {model.noise_variance:.4g} um^2")
    print("  BIC of Q = " + ", ".join(f"{q}: {b:.6g}" for q, b in model.fit.get("bic", []))
          + " (the lowest kept)")


def _fit_ground(args, heights, operators, data):
    """``fit ground``'s one-map rungs on ``heights`` (its spurious points, with --spurious,
    already unmeasured); returns the model."""
    from roughgp.surface_models.fit import fit_surface_model
    z = heights.z
    missing = np.isnan(z)
    err(f"{args.file}: {z.shape[0]} x {z.shape[1]} points, spacing "
        f"{heights.spacing[0]:g} x {heights.spacing[1]:g} um ({heights.spacing_source}), "
        f"{missing.sum()} missing ({missing.mean():.1%}); fitting "
        + ("eq 18 plus noise ..." if args.rung == "eq18" else f"--model {args.rung} ..."))
    if args.rung == "field":
        return fit_field_command(args, heights, operators, data, z)
    if args.rung == "population":
        return fit_population_command(args, [z], heights.spacing, operators, data,
                                      [args.file])
    if args.rung == "periodic":
        model = fit_periodic_command(args, heights, operators, data, z)
        if model is not None:
            return model
        args.rung, args.fell_back = "auto", True
    if args.rung != "eq18":
        return _fit_rungs(args, heights, operators, data, z)
    with refused_by(args.file):
        result = fit_surface_model(z, heights.spacing, **operators, block=args.block,
                                   n_blocks=args.blocks, seed=args.seed, nu=args.nu,
                                   marginal=_marginal_choice(args), data=data,
                                   likelihood=args.likelihood, device=args.device)
    model, fit = result.model, result.block_fit
    hp = model.hyperparameters
    name = "eq 18" if args.nu == 0.5 else f"eq 18 with a Matern nu = {args.nu:g} profile"
    print(f"{name} plus white noise (eq 8) fitted to {args.file}")
    print_operators(model)
    for note in result.texture.cutoffs.reason.split("; ") if result.texture.cutoffs.reason \
            else ():
        print_wrapped(f"note: {note}")
    print(f"  variance (sigma_k^2)  {hp['variance_um2']:>12.5g} um^2")
    print(f"  lambda_a (along)      {hp['lambda_a_um']:>12.5g} um")
    print(f"  lambda_b (across)     {hp['lambda_b_um']:>12.5g} um")
    print(f"  lay angle phi         {hp['angle_deg']:>12.2f} deg (from x, counter-clockwise)")
    print(f"  noise variance        {hp['noise_variance_um2']:>12.4g} um^2")
    if args.likelihood == "whittle":
        print(f"  debiased Whittle log likelihood {fit.log_likelihood:.6g} (all "
              f"{fit.n_points} measured points, {fit.n_frequencies} frequencies)")
    else:
        print(f"  block composite log likelihood {fit.log_likelihood:.6g} ({fit.n_points} "
              f"measured points in {len(fit.blocks)} blocks of {args.block} x {args.block})")
    for note in result.range_notes:
        print_wrapped(f"note: {note}")
    _print_marginal(model)
    return model


def _print_marginal(model):
    if model.marginal_method == "johnson":
        print(f"  heights kept non-Gaussian: skewness {model.marginal['skewness']:.3g}, "
              f"kurtosis {model.marginal['kurtosis']:.3g}")
    elif model.marginal_method == "iaaft":
        q = model.marginal["quantiles_um"]
        print(f"  heights kept as measured (IAAFT): {len(q)} quantiles from {q[0]:.4g} to "
              f"{q[-1]:.4g} um, median {q[len(q) // 2]:.4g} um")
