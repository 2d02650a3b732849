"""``roughgp simulate ground|honed|turned``: draw a surface or a profile and write it.

A ground surface (eq 18 plus the noise of eq 8), a honed surface (eq 19, 20) or a synthetic
turned surface or profile (:mod:`roughgp.models.turned`), written as ``.npy``, ``.csv`` or
``.x3p`` (:mod:`roughgp.io.writers`). Argument handling and messages only.
"""

from __future__ import annotations

import argparse
import dataclasses
import math
import time

import numpy as np

from roughgp.cli.bounds import bounds_text, integer
from roughgp.cli.options import check_scales, seed_or_fresh
from roughgp.cli.output import (
    UsageError,
    add_force_option,
    check_device,
    check_outputs,
    describe_groove,
    err,
    rename_parameters,
)
from roughgp.io.writers import WRITE_FORMATS, write_heights

__all__ = ['MAX_SIMULATE_POINTS', 'add_parser', 'run']


#: Most grid points ``simulate`` draws: 2**24 (e.g. 4096 x 4096). The circulant sampler of
#: eq 18 works on an embedding of at least 4 times the points in complex128, and a honed
#: surface keeps 2 P ground surfaces: 2**24 points already need a few GiB.
MAX_SIMULATE_POINTS = 2 ** 24

_SIMULATE = """\
Draw a synthetic surface (or profile) and write it to --out; the extension picks the format:
.npy (the height array, z[iy, ix]; no spacing stored), .csv (text: a surface one row per y;
a profile as x,z columns; the spacing in a comment line) or .x3p (ISO 25178-72). Heights
and the spacing are in um; the same --seed gives the same surface. A 1-row --shape 1 N
writes a profile.

With --from MODEL.json (a model file of 'roughgp fit') and no KIND, the surface is drawn
from that fitted model instead, at the model's spacing unless --spacing is given, and of
the size of the map (or profile) it was fitted on unless --shape is given (a profile model:
--shape 1 N). The draw is put through the rest of the measurement's operator chain
(the model describes the heights after the F-operator; the file's S- and L-filters follow,
as 'roughgp check' does), so the file holds heights like the measurement's texture heights;
--model-stage writes the draw before them (for 'roughgp texture' to filter).
With --predictive-from SOURCE the draw's model is drawn first, the fit's uncertainty
carried: draws of several seeds then spread as new surfaces of the part would, not as
copies of the fitted crop ('refits': one bootstrap refit; 'sandwich': one parameter set of
eq 18's sandwich covariance; 'tiles': the model given the variance and heights of the fitted
map's 4 x 4 tiles drawn with replacement, the variance's spread widened to a crop's, a
measured PSD their spectrum's shape too, from
--fitted FILE, the measurement it was fitted on; --spurious leaves out its spurious points
as a fit with --spurious did). The chapter "Which model reproduces which measurement" says
what each carries.

examples:
  roughgp simulate ground --shape 2000 2000 --seed 1 --out figure2.x3p     (figure 2)
  roughgp simulate --from land-model.json --shape 256 918 --seed 1 --out new-land.x3p
  roughgp simulate --from left.json --predictive-from tiles --fitted map.x3p --seed 2 \
      --out new-patch.x3p
  roughgp simulate honed --shape 512 512 --seed 1 --out figure3.npy        (figure 3)
  roughgp simulate turned --profile 8192 --seed 1 --out turned.csv"""

_GROUND = """\
A ground surface (section 3.1): a draw of the rotated anisotropic exponential GP of eq 18
(grooves along --angle-deg, correlation length lambda_a along them and lambda_b across)
plus Gaussian noise (eq 8). Default: the hyperparameters of figure 2 (variance 10 um^2,
lambda_a 500 um, lambda_b 5 um, angle 30 deg; noise variance 1 um^2, as in the paper);
each option overrides one of them.

With --target Sq=UM Sal=UM Str=RATIO Std=DEG the hyperparameters are chosen instead so that
the surface has these ISO 25178-2 parameters (beyond the paper; roughgp.targets): the
closed-form inversion sigma_k^2 = Sq^2 - sigma^2, lambda_b = Sal / ln(5 sigma_k^2 / Sq^2),
lambda_a = lambda_b / Str, phi = Std, with the noise variance sigma^2 of --noise-variance
(default 1 um^2: Sq must then exceed 1.118 um; give --noise-variance 0 or a smaller one for
smoother surfaces). The hyperparameters and the achieved Sq, Sal, Str, Std of the drawn
surface are printed; give a field several times Sal/Str long, or Str is undefined on it.

examples:
  roughgp simulate ground --shape 1024 1024 --seed 7 --angle-deg 45 --out ground.npy
  roughgp simulate ground --target Sq=1.2 Sal=40 Str=0.2 Std=30 --noise-variance 0.13 \\
      --shape 1024 1024 --seed 1 --out prescribed.x3p"""

_HONED = """\
A honed surface (section 3.2): per step the minimum of two ground surfaces (eq 18) with
mirrored angles +phi and -phi (eq 19), and the minimum over the steps (eq 20). Default:
the two steps of figure 3 (variance 45 and 0.2 um^2, lambda_a 500 and 5 um, lambda_b 30
and 3 um, phi 45 deg); --step (repeatable) gives your own steps instead.

example:
  roughgp simulate honed --shape 512 512 --seed 3 --out honed.x3p"""

_TURNED = """\
A synthetic, measurement-like turned surface (feed marks along y, the feed along x) or
profile (--profile N or --shape 1 N): the lower envelope of the tool-nose arcs with
feed-mark jitter, tool-edge roughness, side flow and instrument noise (roughgp.models.turned;
default RUBERT_LIKE: feed 250 um, nose radius 800 um, spacing 1 um).

example:
  roughgp simulate turned --profile 8192 --seed 1 --feed 200 --out profile.csv"""



def add_parser(sub, formatter) -> None:
    """Add ``simulate`` and its kinds to the sub-command parsers ``sub``."""
    p = sub.add_parser("simulate", formatter_class=formatter, description=_SIMULATE,
                       help="draw a ground, honed or turned surface to .npy/.csv/.x3p")
    p.add_argument("--from", dest="model", metavar="MODEL.json",
                   help="draw from a model file of 'roughgp fit' (give no KIND)")
    p.add_argument("--shape", nargs=2, type=integer("--shape"), metavar=("NY", "NX"),
                   help="with --from: points along y and x (a profile model: 1 N; default: "
                        "the size of the map the model was fitted on)")
    p.add_argument("--seed", type=integer("--seed"), metavar="S",
                   help=f"with --from: random seed, {bounds_text('--seed')} (default: a fresh "
                        f"one, printed)")
    p.add_argument("--out", metavar="FILE", help="with --from: the output file")
    p.add_argument("--spacing", type=float, metavar="D",
                   help=f"with --from: grid spacing in um, {bounds_text('--spacing')} "
                        f"(default: the model's)")
    p.add_argument("--model-stage", action="store_true",
                   help="with --from: write the draw at the model's stage, before the rest of "
                        "the operator chain (the S- and L-filters)")
    from roughgp.cli.simulate_model import add_predictive_options
    add_predictive_options(p)
    add_force_option(p)
    p.set_defaults(func=run, kind=None)
    kinds = p.add_subparsers(dest="kind", metavar="KIND", required=False,
                             title="kinds (roughgp simulate KIND --help for each)")
    common = argparse.ArgumentParser(add_help=False)
    common.add_argument("--shape", nargs=2, type=integer("--shape"), metavar=("NY", "NX"),
                        help=f"points along y and x (at most {MAX_SIMULATE_POINTS} in all)")
    common.add_argument("--seed", type=integer("--seed"), metavar="S",
                        help=f"random seed, {bounds_text('--seed')} (default: a fresh one, "
                             f"printed)")
    common.add_argument("--out", required=True, metavar="FILE",
                        help="output file: " + ", ".join(WRITE_FORMATS))
    add_force_option(common)
    common.add_argument("--spacing", type=float, default=1.0, metavar="D",
                        help=f"grid spacing in um, {bounds_text('--spacing')} (default 1)")
    grooves = argparse.ArgumentParser(add_help=False)
    grooves.add_argument("--noise-variance", type=float, default=1.0, metavar="V",
                         help="variance of the Gaussian noise of eq 8, um^2 (default 1, the "
                              "paper's); 0 for the latent surface")
    grooves.add_argument("--method", choices=("auto", "circulant", "cholesky"), default="auto",
                         help="exact sampler of eq 10: auto (default) takes the cheaper of a "
                              "Cholesky factor (small grids; on the CPU a grid of many rows "
                              "is factorised row by row, by block Levinson: 64 x 64 in about "
                              "1/7 of the dense time, the same draw) and circulant "
                              "embedding, whose torus must hold the correlation length (about "
                              "6000 x 12000 points for figure 2's lambda_a = 500 um at 1 um)")
    grooves.add_argument("--device", metavar="DEV",
                         help="run the sampler's FFTs or factorisation through torch on DEV: "
                              "cpu, cuda or cuda:N (default: numpy on the CPU); a seed gives "
                              "other numbers on a device than without")

    g = kinds.add_parser("ground", parents=[common, grooves], formatter_class=formatter,
                         description=_GROUND, help="eq 18 ground surface (figure 2)")
    g.add_argument("--preset", choices=("figure2",), default="figure2",
                   help="the hyperparameters to start from (default figure2)")
    g.add_argument("--variance", type=float, metavar="V", help="sigma_k^2 of eq 18, um^2")
    g.add_argument("--lambda-a", type=float, metavar="L",
                   help="correlation length along the grooves, um")
    g.add_argument("--lambda-b", type=float, metavar="L",
                   help="correlation length across the grooves, um")
    g.add_argument("--angle-deg", type=float, metavar="DEG",
                   help="groove direction phi, degrees counter-clockwise from x")
    g.add_argument("--target", nargs="+", metavar="KEY=VALUE",
                   help="prescribe ISO 25178-2 parameters instead of hyperparameters: all of "
                        "Sq=UM Sal=UM Str=RATIO Std=DEG (see above)")
    g.set_defaults(func=run)

    h = kinds.add_parser("honed", parents=[common, grooves], formatter_class=formatter,
                         description=_HONED, help="eq 19/20 honed surface (figure 3)")
    h.add_argument("--preset", choices=("figure3",), default="figure3",
                   help="the honing steps to use unless --step is given (default figure3)")
    h.add_argument("--step", nargs=4, type=float, action="append",
                   metavar=("VARIANCE", "LAMBDA_A", "LAMBDA_B", "ANGLE_DEG"),
                   help="one honing step (um^2, um, um, degrees); repeat for more steps")
    h.set_defaults(func=run)

    t = kinds.add_parser("turned", parents=[common], formatter_class=formatter,
                         description=_TURNED, help="synthetic turned surface or profile")
    t.add_argument("--profile", type=integer("--profile"), metavar="N",
                   help="draw a profile of N points instead of a surface")
    t.add_argument("--feed", type=float, metavar="F",
                   help=f"feed per revolution, {bounds_text('--feed')} (250)")
    t.add_argument("--nose-radius", type=float, metavar="R", help="tool nose radius, um (800)")
    t.add_argument("--noise-sd", type=float, metavar="S",
                   help="instrument noise standard deviation, um (0.05)")
    t.set_defaults(func=run)


def _check_shape(args) -> tuple[int, int]:
    """``(ny, nx)`` from ``--shape NY NX`` or ``--profile N`` (turned), validated."""
    profile = getattr(args, "profile", None)
    if profile is not None and args.shape is not None:
        raise UsageError("give either --shape NY NX or --profile N, not both")
    if profile is not None:
        shape, name = (1, profile), "--profile"
    elif args.shape is not None:
        shape, name = tuple(args.shape), "--shape"
    else:
        raise UsageError("the size is missing: give --shape NY NX (points along y and x)"
                         + (" or --profile N" if hasattr(args, "profile") else ""))
    if any(n < 1 for n in shape):
        raise UsageError(f"{name} must be positive integers (allowed range: 1 to "
                         f"{MAX_SIMULATE_POINTS} points in all), got "
                         f"{' x '.join(map(str, shape))}")
    points = shape[0] * shape[1]
    if points > MAX_SIMULATE_POINTS:
        raise UsageError(f"{name} {' x '.join(map(str, shape))} = {points:.3g} points is an "
                         f"impossible size: simulate draws at most {MAX_SIMULATE_POINTS} "
                         f"points (2**24, e.g. 4096 x 4096; allowed range: 1 to "
                         f"{MAX_SIMULATE_POINTS} points in all)")
    return shape


def _groove(args, preset):
    """The eq 18 hyperparameters: the preset, with the options given on top."""
    from roughgp.models.surfaces import GrooveParameters
    lengthscales = (preset.lengthscales[0] if args.lambda_a is None else args.lambda_a,
                    preset.lengthscales[1] if args.lambda_b is None else args.lambda_b)
    return GrooveParameters(
        variance=preset.variance if args.variance is None else args.variance,
        lengthscales=lengthscales,
        angle=preset.angle if args.angle_deg is None else math.radians(args.angle_deg))



def _parse_targets(pairs) -> dict:
    """``--target KEY=VALUE ...`` as a dict of floats; a usage error names a malformed,
    repeated, unknown or missing key (the keys are those of roughgp.targets)."""
    from roughgp.targets.closed_form import TARGET_NAMES
    values = {}
    for pair in pairs:
        key, sep, text = pair.partition("=")
        key = key.strip()
        if not sep or not key:
            raise UsageError(f"--target takes KEY=VALUE pairs ({', '.join(TARGET_NAMES)}), "
                             f"got {pair!r}")
        if key not in TARGET_NAMES:
            raise UsageError(f"--target: unknown key {key!r}; the keys are "
                             f"{', '.join(TARGET_NAMES)} (all four required)")
        if key in values:
            raise UsageError(f"--target: {key} is given twice")
        try:
            values[key] = float(text)
        except ValueError:
            raise UsageError(f"--target: {key} must be a number, got {text!r}") from None
    missing = [k for k in TARGET_NAMES if k not in values]
    if missing:
        raise UsageError(f"--target: missing {', '.join(missing)}; all of "
                         f"{', '.join(f'{k}=...' for k in TARGET_NAMES)} are required")
    return values


def _target_groove(args, shape):
    """The eq 18 hyperparameters of ``--target`` (the closed form of roughgp.targets)."""
    from roughgp import targets
    given = [opt for opt, value in (("--variance", args.variance),
                                    ("--lambda-a", args.lambda_a),
                                    ("--lambda-b", args.lambda_b),
                                    ("--angle-deg", args.angle_deg)) if value is not None]
    if given:
        raise UsageError(f"--target sets the hyperparameters itself; drop {', '.join(given)}")
    if min(shape) < 3:
        raise UsageError(f"--target prescribes areal parameters: --shape needs at least 3 "
                         f"points along each axis, got {' x '.join(map(str, shape))}")
    values = _parse_targets(args.target)
    try:
        hyper = targets.hyperparameters_for(**values, noise_variance=args.noise_variance,
                                            spacing=args.spacing)
    except ValueError as exc:
        message = rename_parameters(str(exc), {"noise_variance": "--noise-variance"})
        raise UsageError(f"--target: {message}") from None
    err(f"target Sq {values['Sq']:g} um, Sal {values['Sal']:g} um, Str {values['Str']:g}, "
         f"Std {values['Std']:g} deg -> hyperparameters (closed form, roughgp.targets): "
         f"{describe_groove(hyper.groove)}, noise variance {hyper.noise_variance:g} um^2")
    short = targets.field_warning(hyper, shape, args.spacing)
    if short:
        err(f"warning: {short}")
    return hyper.groove, targets.RoughnessTargets(**values)


def _report_achieved(z, spacing, wanted) -> None:
    """The Sq, Sal, Str and Std of the drawn surface against the targets (stderr)."""
    from roughgp import targets
    got = targets.measure(z, spacing)
    units = {"Sq": " um", "Sal": " um", "Str": "", "Std": " deg"}
    parts = [f"{k} {got[k]:.4g}{units[k]} (target {getattr(wanted, k):g})"
             for k in targets.TARGET_NAMES]
    err("achieved on this surface: " + ", ".join(parts))
    if any(math.isnan(got[k]) for k in ("Sal", "Str")):
        err(f"note: nan: the ACF does not decay to 0.2 within the field in some direction; "
             f"the grooves (about Sal/Str = {wanted.Sal / wanted.Str:.4g} um long) need a "
             f"larger --shape")
    err("note: one surface scatters about the targets, most in Sal and Str")


def _report_sampler(steps, shape, spacing, method, device) -> None:
    """Say which exact sampler draws each step's ground surfaces (eq 10) and its cost."""
    from roughgp import sampling
    from roughgp.sampling import block_levinson
    for i, step in enumerate(steps):
        chosen, why = sampling.choose_method(step.covariance(), shape, spacing, device=device)
        which = f"step {i + 1}: " if len(steps) > 1 else ""
        if method == "auto":
            err(f"sampler {which}{chosen} ({why})")
        else:
            err(f"sampler {which}{method} (requested; the cost model: {why})")
        if (chosen if method == "auto" else method) == "cholesky" and device is None \
                and block_levinson.worthwhile(shape):
            err(f"  its factor by block Levinson (the dense factor's draw, about "
                f"{block_levinson.flops(shape):.2g} flops instead of the dense "
                f"{math.prod(shape) ** 3 / 3:.2g})")



def _check_option_scales(args) -> None:
    """The lengths and variances given: finite, in the library's range of scales."""
    options = [(name, getattr(args, attr, None), zero) for name, attr, zero in (
        ("--noise-variance", "noise_variance", True), ("--variance", "variance", False),
        ("--lambda-a", "lambda_a", False), ("--lambda-b", "lambda_b", False),
        ("--feed", "feed", False), ("--nose-radius", "nose_radius", False),
        ("--noise-sd", "noise_sd", True))]
    angle = getattr(args, "angle_deg", None)
    if angle is not None and not math.isfinite(angle):
        raise UsageError(f"--angle-deg must be a finite angle in degrees, got {angle}")
    for v, a, b, phi in getattr(args, "step", None) or ():
        options += [("--step VARIANCE", v, False), ("--step LAMBDA_A", a, False),
                    ("--step LAMBDA_B", b, False)]
        if not math.isfinite(phi):
            raise UsageError(f"--step ANGLE_DEG must be a finite angle in degrees, got {phi}")
    check_scales(*options)


#: The turned model's parameters, as the options of ``simulate turned`` name them.
_TURNED_OPTIONS = {"n": "--profile", "shape": "--shape", "feed": "--feed",
                   "nose_radius": "--nose-radius", "noise_sd": "--noise-sd"}


def _in_options(function, names):
    """``function`` whose ValueErrors name the options (``names``), not the library's words."""
    def call(*a, **k):
        try:
            return function(*a, **k)
        except ValueError as exc:
            raise UsageError(rename_parameters(str(exc), names)) from None
    return call


def _turned_parameters(args):
    """RUBERT_LIKE with --feed, --nose-radius, --noise-sd on top; errors name the options."""
    from roughgp.models import turned
    preset = turned.RUBERT_LIKE
    changes = {k: v for k, v in (("feed", args.feed), ("nose_radius", args.nose_radius),
                                 ("noise_sd", args.noise_sd)) if v is not None}
    if "feed" in changes and not changes["feed"] > 4 * preset.feed_jitter:
        raise UsageError(f"--feed must be > 4 x the feed-mark jitter of the model "
                         f"({preset.feed_jitter:g} um) = {4 * preset.feed_jitter:g} um, got "
                         f"{changes['feed']:g}")
    return _in_options(dataclasses.replace, _TURNED_OPTIONS)(preset, **changes)


def _check_drawn(z) -> None:
    """A non-finite height is an error naming the options that set the scales."""
    if not np.all(np.isfinite(z)):
        bad = int(np.count_nonzero(~np.isfinite(z)))
        raise UsageError(f"the drawn heights are not all finite ({bad} of {z.size}): the "
                         f"scales of --spacing, the variances and the correlation lengths are "
                         f"too far apart for float64; nothing was written")


def run(args) -> int:
    """``roughgp simulate KIND``: draw a surface or a profile and write it to ``--out``."""
    from roughgp.models import surfaces, turned
    if args.kind is None:
        if args.model is None:
            raise UsageError("give a KIND (ground, honed, turned) or --from MODEL.json "
                             "(roughgp simulate --help)")
        from roughgp.cli.simulate_model import run_model
        return run_model(args, _check_shape, _check_drawn, MAX_SIMULATE_POINTS)
    if args.model is not None:
        raise UsageError(f"--from draws from a model file: give it without the KIND "
                         f"{args.kind!r}")
    for option, given in (("--model-stage", args.model_stage),
                          ("--predictive-from", args.predictive_from),
                          ("--fitted", args.fitted), ("--spurious", args.spurious)):
        if given:
            raise UsageError(f"{option} is for a draw from a model file (--from MODEL.json)")
    shape = _check_shape(args)
    out, = check_outputs(("--out", args.out, "heights"), force=args.force)
    _check_option_scales(args)
    seed = seed_or_fresh(args.seed)
    ny, nx = shape
    what = f"{nx}-point profile" if ny == 1 else f"{ny} x {nx}"
    method = getattr(args, "method", None)
    device = getattr(args, "device", None)
    check_device(device)

    wanted = None
    if args.kind == "ground":
        if args.target is not None:
            step, wanted = _target_groove(args, shape)
        else:
            step = _groove(args, surfaces.FIGURE_2)
        label = f"{what} ground {'surface ' if ny > 1 else ''}(eq 18: {describe_groove(step)}, " \
                f"noise variance {args.noise_variance:g} um^2)"
        _report_sampler([step], shape, args.spacing, method, device)
        draw = lambda: surfaces.ground(shape, **dataclasses.asdict(step),  # noqa: E731
                                       noise_variance=args.noise_variance,
                                       spacing=args.spacing, seed=seed, method=method,
                                       device=device)
    elif args.kind == "honed":
        steps = (tuple(surfaces.GrooveParameters(v, (a, b), math.radians(phi))
                       for v, a, b, phi in args.step) if args.step else surfaces.FIGURE_3)
        label = (f"{what} {len(steps)}-step honed {'surface ' if ny > 1 else ''}(eq 19, 20: "
                 + "; ".join(f"step {i + 1}: {describe_groove(s)}" for i, s in enumerate(steps))
                 + f"; noise variance {args.noise_variance:g} um^2)")
        _report_sampler(steps, shape, args.spacing, method, device)
        draw = lambda: surfaces.honed(shape, steps, noise_variance=args.noise_variance,  # noqa
                                      spacing=args.spacing, seed=seed, method=method,
                                      device=device)
    else:
        params = _turned_parameters(args)
        label = (f"{what} turned {'surface ' if ny > 1 else ''}(feed {params.feed:g} um, nose "
                 f"radius {params.nose_radius:g} um, Rt about {params.rt:.3g} um)")
        if ny == 1:
            draw = lambda: turned.turned_profile(nx, args.spacing, params,  # noqa: E731
                                               seed=seed)[1]
        else:
            draw = lambda: turned.turned_surface(shape, args.spacing, params,  # noqa: E731
                                               seed=seed)
        draw = _in_options(draw, {**_TURNED_OPTIONS, "n": "--profile" if args.profile
                                  is not None else "NX of --shape 1 NX"})

    err(f"drawing {label} ...")
    start = time.perf_counter()
    z = np.asarray(draw(), dtype=np.float64)
    if z.ndim == 2 and z.shape[0] == 1:
        z = z[0]  # one row: a profile along x
    _check_drawn(z)
    err(f"drawn in {time.perf_counter() - start:.2f} s; {'Rq' if z.ndim == 1 else 'Sq'} = "
        f"{np.std(z):.4g} um")
    if wanted is not None:
        _report_achieved(z, args.spacing, wanted)
    comment = f"roughgp simulate {args.kind} --seed {seed} --spacing {args.spacing:g}"
    write_heights(out, z, args.spacing, comment)
    err(f"wrote {out} ({'profile' if z.ndim == 1 else 'surface'} of shape {z.shape}, heights "
         f"in um, spacing {args.spacing:g} um)")
    return 0

