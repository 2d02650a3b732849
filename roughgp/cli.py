r"""The ``roughgp`` command: reproduce the paper's claims, simulate surfaces, fit and measure.

A command-line front end to the library, for Jawaid & Seewig, "Model of rough surfaces with
Gaussian processes" (Surf. Topogr.: Metrol. Prop.). Sub-commands:

* ``roughgp reproduce``: run the claims ledger (:mod:`roughgp.claims`) and print the verdicts;
  exit 1 when a check regressed.
* ``roughgp simulate ground|honed|turned``: draw a ground surface (the rotated anisotropic
  exponential GP of eq 18 plus the noise of eq 8), a honed surface (the minimum of mirrored
  ground surfaces, eq 19 and eq 20) or a synthetic turned surface or profile
  (:mod:`roughgp.data`) and write it as ``.npy``, ``.csv`` or ``.x3p``.
* ``roughgp fit``: the spectral-mixture fit of section 3.3 (eq 21) to a profile, or to the
  mean profile of a surface.
* ``roughgp texture``: ISO 25178-2 (surface) or ISO 4287 / 13565-2 (profile) parameters.
* ``roughgp fill``: the unmeasured (NaN) points of a surface filled by the GP posterior mean
  (:mod:`roughgp.gap_filling`), with eq 18 fitted on the measured points (:mod:`roughgp.block_fit`).

Units: heights and lengths (spacing, lengthscales, feed, periods) are in micrometres (um).
Exit codes: 0 success, 1 a claim regressed (``reproduce``), 2 a usage or input error (a
message, never a traceback). :func:`main` is the entry point (``main(argv) -> int``); it never
raises ``SystemExit``.
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import math
import re
import secrets
import sys
import textwrap
import time
import warnings
from pathlib import Path

import numpy as np

__all__ = ["main", "build_parser", "MAX_SIMULATE_POINTS", "WRITE_FORMATS", "READ_FORMATS"]

#: Most grid points ``simulate`` draws: 2**24 (e.g. 4096 x 4096). The circulant sampler of
#: eq 18 works on an embedding of at least 4 times the points in complex128, and a honed
#: surface keeps 2 P ground surfaces: 2**24 points already need a few GiB.
MAX_SIMULATE_POINTS = 2 ** 24
#: Output formats of ``simulate`` (chosen by the file's extension).
WRITE_FORMATS = (".npy", ".csv", ".x3p")
#: Input formats of ``fit`` and ``texture``.
READ_FORMATS = (".npy", ".csv", ".txt", ".dat", ".xyz", ".x3p")

_WIDTH = 100  # the plain-text tables are laid out for a 100-column terminal


class UsageError(Exception):
    """A user error: reported as ``roughgp CMD: error: MESSAGE``, exit code 2."""


def _err(message: str) -> None:
    print(message, file=sys.stderr, flush=True)


def _show_warning(message, category, filename, lineno, file=None, line=None) -> None:
    """Library warnings as one line on stderr (``warning: ...``), without source lines."""
    _err(f"warning: {message}")


# =========================================================================== input / output

@dataclasses.dataclass
class _Heights:
    """Heights read from a file: ``z`` in um (``z[ix]`` or ``z[iy, ix]``), ``spacing`` in
    array order (``(dx,)`` or ``(dy, dx)``), where it came from, and the file's kind."""

    z: np.ndarray
    spacing: tuple
    spacing_source: str

    @property
    def kind(self) -> str:
        return "profile" if self.z.ndim == 1 else "surface"


def _check_input(path: str) -> Path:
    p = Path(path)
    if not p.exists():
        raise UsageError(f"no such file: {path}")
    if not p.is_file():
        raise UsageError(f"not a file: {path}")
    if p.suffix.lower() not in READ_FORMATS:
        raise UsageError(f"cannot read {path}: unknown extension {p.suffix or '(none)'!r}; "
                         f"the formats read are {', '.join(READ_FORMATS)}")
    return p


def _csv_header(path: Path) -> tuple[str | None, float | None]:
    """What a CSV written by ``roughgp simulate`` says about itself in its comment lines:
    ``(kind, spacing)``, each None when not said."""
    kind = spacing = None
    with open(path, encoding="utf-8-sig", errors="replace") as stream:
        for _, line in zip(range(20), stream):
            if not line.startswith("#"):
                break
            m = re.match(r"#\s*roughgp (profile|surface)\b", line)
            kind = m.group(1) if m else kind
            m = re.match(r"#\s*spacing_um:\s*([^\s,;]+)", line)
            if m:
                try:
                    spacing = float(m.group(1))
                except ValueError:
                    pass
    return kind, spacing


def _profile_spacing(x: np.ndarray, path: Path) -> float:
    """The step of a profile's x column; a clear error unless it is regular."""
    from roughgp.readers import MalformedFileError
    steps = np.diff(x)
    step = float((x[-1] - x[0]) / (x.size - 1))
    if np.max(np.abs(steps - step)) > 1e-6 * step:
        raise MalformedFileError(f"{path}: the x column is not a regular grid (steps from "
                                 f"{steps.min():.6g} to {steps.max():.6g}); roughgp needs "
                                 "equally spaced points")
    return step


def _read(path_text: str, *, kind: str = "auto", spacing: float | None = None) -> _Heights:
    """Read a profile or a surface (heights in um) from any of :data:`READ_FORMATS`.

    ``kind`` forces "profile" or "surface" for text tables; ``spacing`` (um) overrides the
    file's own (x3p, xyz, a profile's x column, the comment of a ``roughgp simulate`` CSV);
    without either it is 1 um.
    """
    from roughgp import readers
    path = _check_input(path_text)
    if spacing is not None and not (math.isfinite(spacing) and spacing > 0):
        raise UsageError(f"--spacing must be > 0 (um), got {spacing!r}")
    ext = path.suffix.lower()
    if ext == ".npy":
        with open(path, "rb") as stream:
            if stream.read(6) != b"\x93NUMPY":
                raise readers.MalformedFileError(f"{path}: not a .npy file (no NumPy header)")
        try:
            z = np.load(path, allow_pickle=False)
        except (ValueError, OSError, EOFError) as exc:
            raise readers.MalformedFileError(f"{path}: not a readable .npy array ({exc})") \
                from None
        if z.ndim == 2 and z.shape[0] == 1 and kind != "surface":
            z = z[0]
        if z.ndim not in (1, 2) or not np.issubdtype(z.dtype, np.number):
            raise readers.MalformedFileError(f"{path}: expected a numeric profile (1-D) or "
                                             f"surface (2-D), got {z.dtype} of shape "
                                             f"{z.shape}")
        z = np.asarray(z, dtype=np.float64)
        d = 1.0 if spacing is None else spacing
        source = ("from --spacing" if spacing is not None
                  else "assumed: a .npy file stores none; give --spacing")
        return _Heights(z, (d,) * z.ndim, source)
    if ext == ".x3p":
        hm = readers.read_x3p(path)
        if spacing is not None:
            return _Heights(hm.z, (spacing,) * hm.z.ndim, "from --spacing, not the file's")
        return _Heights(hm.z, tuple(hm.spacing), "from the x3p file")
    if ext == ".xyz":
        z, (dy, dx) = readers.read_xyz(path)
        if spacing is not None:
            return _Heights(z, (spacing, spacing), "from --spacing, not the file's")
        return _Heights(z, (dy, dx), "from the x y positions")

    # text tables: a roughgp CSV says what it is; otherwise 1 or 2 columns are a profile
    header_kind, header_spacing = _csv_header(path)
    table, _ = readers.read_surface(path, spacing=1.0)
    if kind == "auto":
        kind = header_kind or ("profile" if table.shape[1] <= 2 else "surface")
    if spacing is not None:
        step, source = spacing, "from --spacing"
    elif header_spacing is not None:
        step, source = header_spacing, "from the file's spacing_um comment"
    else:
        step, source = 1.0, "assumed: the file states none; give --spacing"
    if kind == "surface":
        return _Heights(table, (step, step), source)
    if table.shape[1] == 1:  # heights only
        _, z = readers.read_profile(path, spacing=step)
        return _Heights(z, (step,), source)
    x, z = readers.read_profile(path)  # x, z columns
    if spacing is None:
        step, source = _profile_spacing(x, path), "from the x column"
    return _Heights(z, (step,), source)


def _check_output(path_text: str) -> Path:
    path = Path(path_text)
    if path.suffix.lower() not in WRITE_FORMATS:
        raise UsageError(f"cannot write {path_text}: unknown extension "
                         f"{path.suffix or '(none)'!r}; the output formats are "
                         f"{', '.join(WRITE_FORMATS)} (.npy: the height array; .csv: text "
                         f"that fit and texture read back; .x3p: ISO 25178-72)")
    if path.is_dir():
        raise UsageError(f"--out {path_text} is a directory; give a file name")
    return path


def _write(path: Path, z: np.ndarray, spacing: float, comment: str) -> None:
    """Write heights ``z`` (um) in the format of the extension (:data:`WRITE_FORMATS`)."""
    from roughgp import readers
    path.parent.mkdir(parents=True, exist_ok=True)
    ext = path.suffix.lower()
    if ext == ".npy":
        np.save(path, z)
    elif ext == ".x3p":
        readers.write_x3p(path, z, spacing, comment=comment)
    elif z.ndim == 1:  # the (x, z) columns that readers.read_profile reads
        with open(path, "w", encoding="utf-8", newline="\n") as out:
            out.write(f"# roughgp profile: x and z in micrometres ({comment})\n"
                      f"# spacing_um: {spacing!r}\n"
                      "x_um,z_um\n")
            np.savetxt(out, np.column_stack((np.arange(z.size) * spacing, z)),
                       fmt="%.12g", delimiter=",")
    else:  # one row per y, columns x: what readers.read_surface reads
        with open(path, "w", encoding="utf-8", newline="\n") as out:
            out.write(f"# roughgp surface: z[iy, ix] in micrometres, one row per y "
                      f"({comment})\n"
                      f"# spacing_um: {spacing!r}\n"
                      f"# shape: {z.shape[0]} {z.shape[1]}\n")
            np.savetxt(out, z, fmt="%.12g", delimiter=",")


def _json_value(value):
    """JSON-ready: numpy scalars to Python, NaN / inf to None."""
    if isinstance(value, dict):
        return {k: _json_value(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_json_value(v) for v in value]
    if isinstance(value, (np.floating, float)):
        return float(value) if math.isfinite(value) else None
    if isinstance(value, np.integer):
        return int(value)
    return value


def _write_json(path_text: str, record: dict) -> None:
    path = Path(path_text)
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(json.dumps(_json_value(record), indent=1) + "\n", encoding="utf-8")
    _err(f"wrote {path}")


# =========================================================================== reproduce

def _wrap(text: str, width: int) -> list[str]:
    return textwrap.wrap(str(text), width, break_on_hyphens=False) or [""]


def _print_wrapped(text: str, indent: str = "  ") -> None:
    print(textwrap.fill(text, _WIDTH, initial_indent=indent, subsequent_indent=indent + "  "))


def _table(rows: list[tuple], widths: tuple[int, ...], header: tuple) -> str:
    """A plain-text table; each cell wrapped to its column's width."""
    lines = []
    for row in [header, tuple("-" * w for w in widths)] + rows:
        cells = [_wrap(c, w) for c, w in zip(row, widths)]
        for k in range(max(len(c) for c in cells)):
            parts = [(c[k] if k < len(c) else "").ljust(w) for c, w in zip(cells, widths)]
            lines.append("  ".join(parts).rstrip())
    return "\n".join(lines)


def cmd_reproduce(args) -> int:
    """``roughgp reproduce``: run the claims ledger, print it, exit 1 on a regression."""
    from roughgp import claims
    if args.list:
        for c in claims.CLAIMS:
            print(f"{c.key}  ({c.where}; {c.verdict})")
            for line in _wrap(c.statement, _WIDTH - 4):
                print(f"    {line}")
        return 0
    for key in args.only or ():
        try:
            claims.claim(key)
        except ValueError as exc:
            raise UsageError(f"--only: {exc}") from None
    if "matplotlib.pyplot" not in sys.modules:
        import matplotlib
        matplotlib.use("Agg")  # checks draw figures; never open a window
    out = Path(args.out) if args.out else None
    if out is not None and out.exists() and not out.is_dir():
        raise UsageError(f"--out {args.out} exists and is not a directory")
    start = time.perf_counter()
    outcomes = claims.run(full=args.full, only=args.only,
                          figures_dir=None if out is None else out / "figures",
                          progress=_err)
    rows = [(o.claim.key, o.claim.verdict, o.status,
             o.value if o.error is None else f"{o.value} ({o.error})") for o in outcomes]
    key_width = min(28, max([5] + [len(o.claim.key) for o in outcomes]))
    widths = (key_width, 18, 9, _WIDTH - key_width - 18 - 9 - 6)
    print(_table(rows, widths, ("claim", "verdict", "status", "our value")))
    regressed = [o.claim.key for o in outcomes if o.regressed]
    print(f"\n{len(outcomes)} claim(s) in {time.perf_counter() - start:.1f} s"
          f"{' (paper sizes)' if args.full else ''}: "
          f"{len(outcomes) - len(regressed)} ok, {len(regressed)} regressed")
    if out is not None:
        md, js = claims.write(outcomes, out)
        _err(f"wrote {md}, {js} and the figures in {out / 'figures'}")
    if regressed:
        _err(f"REGRESSED (the verdict must be revisited): {', '.join(regressed)}")
        return 1
    return 0


# =========================================================================== simulate

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
    from roughgp.surfaces import GrooveParameters
    lengthscales = (preset.lengthscales[0] if args.lambda_a is None else args.lambda_a,
                    preset.lengthscales[1] if args.lambda_b is None else args.lambda_b)
    return GrooveParameters(
        variance=preset.variance if args.variance is None else args.variance,
        lengthscales=lengthscales,
        angle=preset.angle if args.angle_deg is None else math.radians(args.angle_deg))


def _describe(step) -> str:
    return (f"variance {step.variance:g} um^2, lambda_a {step.lengthscales[0]:g} um, "
            f"lambda_b {step.lengthscales[1]:g} um, angle {math.degrees(step.angle):g} deg")


def _parse_targets(pairs) -> dict:
    """``--target KEY=VALUE ...`` as a dict of floats; a usage error names a malformed,
    repeated, unknown or missing key (the keys are those of roughgp.targets)."""
    from roughgp.targets import TARGET_NAMES
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
        raise UsageError(f"--target: {exc}") from None
    _err(f"target Sq {values['Sq']:g} um, Sal {values['Sal']:g} um, Str {values['Str']:g}, "
         f"Std {values['Std']:g} deg -> hyperparameters (closed form, roughgp.targets): "
         f"{_describe(hyper.groove)}, noise variance {hyper.noise_variance:g} um^2")
    short = targets.field_warning(hyper, shape, args.spacing)
    if short:
        _err(f"warning: {short}")
    return hyper.groove, targets.RoughnessTargets(**values)


def _report_achieved(z, spacing, wanted) -> None:
    """The Sq, Sal, Str and Std of the drawn surface against the targets (stderr)."""
    from roughgp import targets
    got = targets.measure(z, spacing)
    units = {"Sq": " um", "Sal": " um", "Str": "", "Std": " deg"}
    parts = [f"{k} {got[k]:.4g}{units[k]} (target {getattr(wanted, k):g})"
             for k in targets.TARGET_NAMES]
    _err("achieved on this surface: " + ", ".join(parts))
    if any(math.isnan(got[k]) for k in ("Sal", "Str")):
        _err(f"note: nan: the ACF does not decay to 0.2 within the field in some direction; "
             f"the grooves (about Sal/Str = {wanted.Sal / wanted.Str:.4g} um long) need a "
             f"larger --shape")
    _err("note: one surface scatters about the targets, most in Sal and Str")


def _report_sampler(steps, shape, spacing, method) -> None:
    """Say which exact sampler draws each step's ground surfaces (eq 10) and its cost."""
    from roughgp import sampling
    for i, step in enumerate(steps):
        chosen, why = sampling.choose_method(step.kernel(), shape, spacing)
        which = f"step {i + 1}: " if len(steps) > 1 else ""
        if method == "auto":
            _err(f"sampler {which}{chosen} ({why})")
        else:
            _err(f"sampler {which}{method} (requested; the cost model: {why})")


def cmd_simulate(args) -> int:
    """``roughgp simulate KIND``: draw a surface or a profile and write it to ``--out``."""
    from roughgp import data, surfaces
    shape = _check_shape(args)
    out = _check_output(args.out)
    if not (math.isfinite(args.spacing) and args.spacing > 0):
        raise UsageError(f"--spacing must be > 0 (um), got {args.spacing!r}")
    seed = args.seed
    if seed is None:
        seed = secrets.randbelow(2 ** 31)
        _err(f"seed: {seed} (pass --seed {seed} to draw the same surface again)")
    ny, nx = shape
    what = f"{nx}-point profile" if ny == 1 else f"{ny} x {nx}"
    method = getattr(args, "method", None)
    device = getattr(args, "device", None)
    if device is not None:
        from roughgp.device import resolve
        try:
            resolve(device, name="--device")
        except ValueError as exc:
            raise UsageError(str(exc)) from None

    wanted = None
    if args.kind == "ground":
        if args.target is not None:
            step, wanted = _target_groove(args, shape)
        else:
            step = _groove(args, surfaces.FIGURE_2)
        label = f"{what} ground {'surface ' if ny > 1 else ''}(eq 18: {_describe(step)}, " \
                f"noise variance {args.noise_variance:g} um^2)"
        _report_sampler([step], shape, args.spacing, method)
        draw = lambda: surfaces.ground(shape, **dataclasses.asdict(step),  # noqa: E731
                                       noise_variance=args.noise_variance,
                                       spacing=args.spacing, seed=seed, method=method,
                                       device=device)
    elif args.kind == "honed":
        steps = (tuple(surfaces.GrooveParameters(v, (a, b), math.radians(phi))
                       for v, a, b, phi in args.step) if args.step else surfaces.FIGURE_3)
        label = (f"{what} {len(steps)}-step honed {'surface ' if ny > 1 else ''}(eq 19, 20: "
                 + "; ".join(f"step {i + 1}: {_describe(s)}" for i, s in enumerate(steps))
                 + f"; noise variance {args.noise_variance:g} um^2)")
        _report_sampler(steps, shape, args.spacing, method)
        draw = lambda: surfaces.honed(shape, steps, noise_variance=args.noise_variance,  # noqa
                                      spacing=args.spacing, seed=seed, method=method,
                                      device=device)
    else:
        changes = {k: v for k, v in (("feed", args.feed), ("nose_radius", args.nose_radius),
                                     ("noise_sd", args.noise_sd)) if v is not None}
        params = dataclasses.replace(data.RUBERT_LIKE, **changes)
        label = (f"{what} turned {'surface ' if ny > 1 else ''}(feed {params.feed:g} um, nose "
                 f"radius {params.nose_radius:g} um, Rt about {params.rt:.3g} um)")
        if ny == 1:
            draw = lambda: data.turned_profile(nx, args.spacing, params,  # noqa: E731
                                               seed=seed)[1]
        else:
            draw = lambda: data.turned_surface(shape, args.spacing, params,  # noqa: E731
                                               seed=seed)

    _err(f"drawing {label} ...")
    start = time.perf_counter()
    z = np.asarray(draw(), dtype=np.float64)
    if z.ndim == 2 and z.shape[0] == 1:
        z = z[0]  # one row: a profile along x
    _err(f"drawn in {time.perf_counter() - start:.2f} s; Sq = {np.std(z):.4g} um")
    if wanted is not None:
        _report_achieved(z, args.spacing, wanted)
    comment = f"roughgp simulate {args.kind} --seed {seed} --spacing {args.spacing:g}"
    _write(out, z, args.spacing, comment)
    _err(f"wrote {out} ({'profile' if z.ndim == 1 else 'surface'} of shape {z.shape}, heights "
         f"in um, spacing {args.spacing:g} um)")
    return 0


# =========================================================================== fit

def _to_profile(heights: _Heights, axis: str) -> tuple[np.ndarray, float, str]:
    """A profile (z, spacing, how) from a profile or a surface (mean profile)."""
    if heights.kind == "profile":
        return heights.z, heights.spacing[0], "the profile as read"
    z = heights.z
    if axis == "x":
        profile, spacing = np.nanmean(z, axis=0), heights.spacing[1]
        how = (f"mean profile along x: the {z.shape[0]} rows averaged (over y, along the lay "
               "of feed marks that run along y)")
    else:
        profile, spacing = np.nanmean(z, axis=1), heights.spacing[0]
        how = f"mean profile along y: the {z.shape[1]} columns averaged (over x)"
    return profile, spacing, how


def cmd_fit(args) -> int:
    """``roughgp fit FILE``: the spectral-mixture fit (eq 21) of section 3.3."""
    from roughgp import fitting, levelling
    if args.mixtures < 1:
        raise UsageError(f"--mixtures must be >= 1, got {args.mixtures}")
    if args.candidates < 1:
        raise UsageError(f"--candidates must be >= 1, got {args.candidates}")
    heights = _read(args.file, kind=args.kind, spacing=args.spacing)
    z, spacing, how = _to_profile(heights, args.axis)
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
        _err(f"note: {z.size} points; the exact likelihood costs O(n^2) per step, so this "
             "can take many minutes (crop or decimate the profile for a quicker look)")
    _err(f"fitting Q = {args.mixtures} spectral-mixture components (eq 21) to {z.size} points "
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
    _print_wrapped(f"profile: {how}; {z.size} points, spacing {spacing:g} um "
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
        _write_json(args.out, {
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


# =========================================================================== texture

_UNITS = {"Ssk": "", "Sku": "", "Rsk": "", "Rku": "", "Str": "", "Std": "deg",
          "Smr1": "%", "Smr2": "%", "Mr1": "%", "Mr2": "%"}


def _unit(name: str) -> str:
    """The unit of a texture parameter: um unless listed in ``_UNITS``."""
    return _UNITS.get(name, "um")


def cmd_texture(args) -> int:
    """``roughgp texture FILE``: ISO surface-texture parameters."""
    from roughgp import texture
    heights = _read(args.file, kind=args.kind, spacing=args.spacing)
    if heights.kind == "surface":
        values = texture.areal_parameters(heights.z, spacing=heights.spacing,
                                          level=args.level, undefined="nan")
        standard = "ISO 25178-2 areal parameters"
    else:
        values = texture.profile_parameters(heights.z, spacing=heights.spacing[0],
                                            level=args.level, undefined="nan")
        standard = "ISO 4287 / ISO 13565-2 profile parameters (whole profile, unfiltered)"
    shape = " x ".join(map(str, heights.z.shape))
    spacing = ", ".join(f"{d:g}" for d in heights.spacing)
    print(f"{standard} of {args.file}")
    _print_wrapped(f"{heights.kind} of {shape} points, spacing {spacing} um "
                   f"({heights.spacing_source}); heights referred to the "
                   f"{'least-squares plane' if args.level else 'mean'}")
    for name, value in values.items():
        print(f"  {name:<5} {value:>12.5g} {_unit(name)}".rstrip())
    if args.json:
        _write_json(args.json, {"file": str(args.file), "kind": heights.kind,
                                "shape": list(heights.z.shape),
                                "spacing_um": list(heights.spacing),
                                "spacing_from": heights.spacing_source,
                                "level": args.level, "parameters": values,
                                "units": {k: _unit(k) for k in values}})
    return 0


# =========================================================================== fill

def cmd_fill(args) -> int:
    """``roughgp fill FILE``: fill the unmeasured points of a surface with the GP posterior."""
    from roughgp import levelling
    from roughgp.block_fit import fit_ground_to_valid_points
    from roughgp.device import resolve
    from roughgp.gap_filling import fill_gaps
    out = _check_output(args.out)
    sd_out = _check_output(args.sd) if args.sd else None
    if args.samples < 0:
        raise UsageError(f"--samples must be >= 0, got {args.samples}")
    if sd_out is not None and args.samples < 2:
        raise UsageError("--sd needs --samples >= 2 (the sd is estimated from the draws)")
    try:
        resolve(args.device, name="--device")
    except ValueError as exc:
        raise UsageError(str(exc)) from None
    heights = _read(args.file, kind="surface", spacing=args.spacing)
    if heights.kind != "surface":
        raise UsageError(f"{args.file} holds a profile; fill needs a surface z[iy, ix]")
    (dy, dx), z = heights.spacing, heights.z
    spacing = dx if dy == dx else (dy, dx)
    if dy != dx and ".csv" in {out.suffix.lower(), (sd_out or out).suffix.lower()}:
        raise UsageError(f"the spacing differs along y and x ({dy:g}, {dx:g} um): a .csv "
                         f"stores one spacing; write .x3p or .npy")
    missing = np.isnan(z)
    if not missing.any():
        raise UsageError(f"{args.file} has no missing (NaN) point: nothing to fill")
    _err(f"{args.file}: {z.shape[0]} x {z.shape[1]} points, spacing {dy:g} x {dx:g} um "
         f"({heights.spacing_source}), {missing.sum()} missing ({missing.mean():.1%})")
    levelled, plane = levelling.level(z, spacing=heights.spacing, return_coefficients=True)
    start = time.perf_counter()
    fit = fit_ground_to_valid_points(levelled, spacing=heights.spacing, block=args.block,
                                     n_blocks=args.blocks, seed=args.seed)
    g = fit.groove
    _err(f"eq 18 fitted on {fit.n_points} measured points of {len(fit.blocks)} blocks in "
         f"{time.perf_counter() - start:.1f} s: {_describe(g)}, noise variance "
         f"{fit.noise_variance:.4g} um^2")
    fill = fill_gaps(levelled, fit.kernel, noise_variance=fit.noise_variance,
                     spacing=heights.spacing, n_samples=args.samples, seed=args.seed,
                     device=args.device)
    if not fill.converged:
        _err("warning: conjugate gradients did not reach their tolerance; the fill is "
             "approximate")
    iy, ix = np.indices(z.shape)
    tilt = plane.offset + plane.slope[0] * iy * dy + plane.slope[1] * ix * dx
    filled = np.where(missing, fill.mean + tilt, z)
    _err(f"filled in {fill.seconds:.1f} s ({fill.iterations} CG iterations"
         + (f", {args.samples} draws for the sd" if args.samples else "") + ")")
    comment = f"roughgp fill {Path(args.file).name} --seed {args.seed}"
    _write(out, filled, spacing, comment)
    _err(f"wrote {out} (the measured heights, the {missing.sum()} missing ones filled by the "
         f"posterior mean)")
    if sd_out is not None:
        _write(sd_out, np.where(missing, fill.sd, 0.0), spacing, comment + " (posterior sd)")
        sd = fill.sd[missing]
        _err(f"wrote {sd_out} (posterior sd of the latent surface at the filled points, 0 at "
             f"measured ones; median {np.median(sd):.3g} um, largest {sd.max():.3g} um)")
    return 0


# =========================================================================== the parser

_DESCRIPTION = """\
Rough surfaces as Gaussian processes: the companion of Jawaid & Seewig, "Model of rough
surfaces with Gaussian processes". Heights and lengths are in micrometres (um) throughout.

examples:
  roughgp reproduce --out ledger/              check every claim of the paper
  roughgp simulate ground --shape 512 512 --seed 1 --out ground.x3p
  roughgp simulate turned --profile 4096 --seed 1 --out turned.csv
  roughgp fit turned.csv --out fit.json        spectral-mixture fit (eq 21)
  roughgp texture ground.x3p                   ISO 25178-2 parameters (Sq, Ssk, Sal, ...)
  roughgp fill measured.x3p --out filled.x3p   missing (NaN) points filled by the GP

exit codes: 0 success, 1 a claim regressed (reproduce), 2 a usage or input error."""

_SIMULATE = """\
Draw a synthetic surface (or profile) and write it to --out; the extension picks the format:
.npy (the height array, z[iy, ix]; no spacing stored), .csv (text: a surface one row per y;
a profile as x,z columns; the spacing in a comment line) or .x3p (ISO 25178-72). Heights
and the spacing are in um; the same --seed gives the same surface. A 1-row --shape 1 N
writes a profile.

examples:
  roughgp simulate ground --shape 2000 2000 --seed 1 --out figure2.x3p     (figure 2)
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
feed-mark jitter, tool-edge roughness, side flow and instrument noise (roughgp.data;
default RUBERT_LIKE: feed 250 um, nose radius 800 um, spacing 1 um).

example:
  roughgp simulate turned --profile 8192 --seed 1 --feed 200 --out profile.csv"""

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

_TEXTURE = """\
Print ISO surface-texture parameters: for a surface the ISO 25178-2 set (Sa, Sq, Ssk, Sku,
Sp, Sv, Sz, Sal, Str, Std, Sk, Spk, Svk, Smr1, Smr2), for a profile ISO 4287 / 13565-2 (Ra,
Rq, Rsk, Rku, Rp, Rv, Rt, RSm, Rk, Rpk, Rvk, Mr1, Mr2), without filtering. Heights and
lengths in um, Std in degrees, material ratios in percent. A parameter the data do not
define (e.g. the skewness of a flat surface) prints as nan (null in the JSON).

example:
  roughgp texture ground.x3p --level --json texture.json"""

_FILL = """\
Fill the unmeasured (NaN) points of a surface, e.g. the non-measured points an optical
instrument leaves at steep flanks: the surface is levelled (least-squares plane), eq 18 plus
white noise is fitted to the measured points alone (block composite likelihood,
roughgp.block_fit), and the missing points get the GP posterior mean (roughgp.gap_filling,
conjugate gradients with FFT products). --sd also writes the posterior standard deviation
at the filled points (pathwise draws). Suited to stationary, ground-like textures; heights
and lengths in um.

example:
  roughgp fill measured.x3p --out filled.x3p --sd sd.x3p --seed 0"""

_INPUT = f"""\
input formats: {', '.join(READ_FORMATS)}
  .npy              a 1-D profile or a 2-D surface z[iy, ix] (no spacing stored: --spacing)
  .csv .txt .dat    text tables: 1 column (heights) or 2 columns (x, z) are a profile, 3 or
                    more a surface (one row per y); a CSV written by 'roughgp simulate' says
                    which it is and its spacing in a comment line
  .xyz              x y z points on a regular grid
  .x3p              ISO 25178-72 (heights and spacing from the file)"""


class _formatter(argparse.RawDescriptionHelpFormatter):
    """Descriptions kept as written; option help in a column at 20 or more."""

    def __init__(self, prog):
        super().__init__(prog, width=_WIDTH, max_help_position=32)
        self._action_max_length = 16  # so "reproduce" keeps its help on its line


def _add_input_options(parser) -> None:
    parser.add_argument("file", metavar="FILE",
                        help="the profile or surface, heights in um (formats: see below)")
    parser.add_argument("--spacing", type=float, metavar="D",
                        help="the grid spacing in um, overriding the file's (default: from the "
                             "file; 1 um when it has none, e.g. .npy)")
    parser.add_argument("--kind", choices=("auto", "profile", "surface"), default="auto",
                        help="read a text table as a profile or a surface (default: auto)")


def build_parser() -> argparse.ArgumentParser:
    """The ``roughgp`` argument parser (all sub-commands)."""
    from roughgp import __version__
    parser = argparse.ArgumentParser(prog="roughgp", description=_DESCRIPTION,
                                     formatter_class=_formatter)
    parser.add_argument("--version", action="version", version=f"roughgp {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND",
                                title="commands (roughgp COMMAND --help for each)")

    p = sub.add_parser("reproduce", formatter_class=_formatter,
                       help="run the claims ledger: every checkable claim of the paper",
                       description="Run the checks of the claims ledger (roughgp.claims) and "
                                   "print each claim's verdict, status and our value;\nexit 1 "
                                   "when a check regressed (progress goes to stderr, the table "
                                   "to stdout).\n\nexamples:\n"
                                   "  roughgp reproduce --list\n"
                                   "  roughgp reproduce --only eq5-duality --out ledger/")
    p.add_argument("--full", action="store_true",
                   help="use the paper's sizes (slower) instead of the quick defaults")
    p.add_argument("--only", nargs="+", metavar="KEY",
                   help="run only these claims (see --list)")
    p.add_argument("--out", metavar="DIR",
                   help="write DIR/ledger.md, DIR/ledger.json and DIR/figures/KEY.png")
    p.add_argument("--list", action="store_true", help="list the claims and exit")
    p.set_defaults(func=cmd_reproduce)

    p = sub.add_parser("simulate", formatter_class=_formatter, description=_SIMULATE,
                       help="draw a ground, honed or turned surface to .npy/.csv/.x3p")
    kinds = p.add_subparsers(dest="kind", metavar="KIND", required=True,
                             title="kinds (roughgp simulate KIND --help for each)")
    common = argparse.ArgumentParser(add_help=False)
    common.add_argument("--shape", nargs=2, type=int, metavar=("NY", "NX"),
                        help=f"points along y and x (at most {MAX_SIMULATE_POINTS} in all)")
    common.add_argument("--seed", type=int, metavar="S",
                        help="random seed (default: a fresh one, printed)")
    common.add_argument("--out", required=True, metavar="FILE",
                        help="output file: " + ", ".join(WRITE_FORMATS))
    common.add_argument("--spacing", type=float, default=1.0, metavar="D",
                        help="grid spacing in um (default 1)")
    grooves = argparse.ArgumentParser(add_help=False)
    grooves.add_argument("--noise-variance", type=float, default=1.0, metavar="V",
                         help="variance of the Gaussian noise of eq 8, um^2 (default 1, the "
                              "paper's); 0 for the latent surface")
    grooves.add_argument("--method", choices=("auto", "circulant", "cholesky"), default="auto",
                         help="exact sampler of eq 10: auto (default) takes the cheaper of a "
                              "dense Cholesky factor (small grids) and circulant embedding, "
                              "whose torus must hold the correlation length (about 6000 x "
                              "12000 points for figure 2's lambda_a = 500 um at 1 um)")
    grooves.add_argument("--device", metavar="DEV",
                         help="run the sampler's FFTs or factorisation through torch on DEV: "
                              "cpu, cuda or cuda:N (default: numpy on the CPU); a seed gives "
                              "other numbers on a device than without")

    g = kinds.add_parser("ground", parents=[common, grooves], formatter_class=_formatter,
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
    g.set_defaults(func=cmd_simulate)

    h = kinds.add_parser("honed", parents=[common, grooves], formatter_class=_formatter,
                         description=_HONED, help="eq 19/20 honed surface (figure 3)")
    h.add_argument("--preset", choices=("figure3",), default="figure3",
                   help="the honing steps to use unless --step is given (default figure3)")
    h.add_argument("--step", nargs=4, type=float, action="append",
                   metavar=("VARIANCE", "LAMBDA_A", "LAMBDA_B", "ANGLE_DEG"),
                   help="one honing step (um^2, um, um, degrees); repeat for more steps")
    h.set_defaults(func=cmd_simulate)

    t = kinds.add_parser("turned", parents=[common], formatter_class=_formatter,
                         description=_TURNED, help="synthetic turned surface or profile")
    t.add_argument("--profile", type=int, metavar="N",
                   help="draw a profile of N points instead of a surface")
    t.add_argument("--feed", type=float, metavar="F", help="feed per revolution, um (250)")
    t.add_argument("--nose-radius", type=float, metavar="R", help="tool nose radius, um (800)")
    t.add_argument("--noise-sd", type=float, metavar="S",
                   help="instrument noise standard deviation, um (0.05)")
    t.set_defaults(func=cmd_simulate)

    f = sub.add_parser("fit", formatter_class=_formatter, description=_FIT, epilog=_INPUT,
                       help="spectral-mixture fit (eq 21) of a profile")
    _add_input_options(f)
    f.add_argument("--mixtures", type=int, default=5, metavar="Q",
                   help="number of spectral-mixture components (default 5, the paper's)")
    f.add_argument("--seed", type=int, default=0, metavar="S",
                   help="seed of the fit's initialisations (default 0)")
    f.add_argument("--candidates", type=int, default=10, metavar="N",
                   help="initialisations scored (default 10)")
    f.add_argument("--axis", choices=("x", "y"), default="x",
                   help="for a surface: the direction of the mean profile (default x)")
    f.add_argument("--out", metavar="RESULT.json", help="write the fit as JSON")
    f.set_defaults(func=cmd_fit)

    x = sub.add_parser("texture", formatter_class=_formatter, description=_TEXTURE,
                       epilog=_INPUT,
                       help="ISO texture parameters (Sq, Sal, Str, ... / Ra, Rq, ...)")
    _add_input_options(x)
    x.add_argument("--level", action="store_true",
                   help="refer heights to the least-squares plane / line (default: the mean)")
    x.add_argument("--json", metavar="OUT", help="also write the parameters as JSON")
    x.set_defaults(func=cmd_texture)

    f = sub.add_parser("fill", formatter_class=_formatter, description=_FILL, epilog=_INPUT,
                       help="fill the missing (NaN) points of a surface with the GP")
    f.add_argument("file", metavar="FILE", help="the surface, heights in um, NaN where missing")
    f.add_argument("--spacing", type=float, metavar="D",
                   help="the grid spacing in um, overriding the file's")
    f.add_argument("--out", required=True, metavar="FILE",
                   help="the filled surface: " + ", ".join(WRITE_FORMATS))
    f.add_argument("--sd", metavar="FILE", help="also write the posterior sd map")
    f.add_argument("--samples", type=int, default=16, metavar="N",
                   help="pathwise draws for the sd (default 16; 0: the mean only)")
    f.add_argument("--seed", type=int, default=0, metavar="S",
                   help="seed of the blocks chosen for the fit and of the draws (default 0)")
    f.add_argument("--block", type=int, default=24, metavar="B",
                   help="side of the fit's blocks in points (default 24)")
    f.add_argument("--blocks", type=int, default=12, metavar="K",
                   help="blocks used by the fit (default 12)")
    f.add_argument("--device", metavar="DEV",
                   help="run the fill's FFTs and CG through torch on DEV (cpu, cuda, cuda:N)")
    f.set_defaults(func=cmd_fill)
    return parser


def main(argv=None) -> int:
    """Run ``roughgp`` with ``argv`` (default ``sys.argv[1:]``); returns the exit code."""
    from roughgp.readers import MalformedFileError
    parser = build_parser()
    try:
        args = parser.parse_args(argv)
    except SystemExit as exc:  # --help, --version (0) and argparse's usage errors (2)
        return exc.code if isinstance(exc.code, int) else (0 if exc.code is None else 2)
    if args.command is None:
        parser.print_help(sys.stderr)
        return 2
    name = f"roughgp {args.command}" + (f" {args.kind}" if args.command == "simulate" else "")
    try:
        with warnings.catch_warnings():
            warnings.showwarning = _show_warning
            return args.func(args)
    except (UsageError, MalformedFileError, ValueError) as exc:
        _err(f"{name}: error: {exc}")
        return 2
    except OSError as exc:  # unreadable / unwritable files
        _err(f"{name}: error: {exc.strerror or exc}"
             + (f": {exc.filename}" if getattr(exc, "filename", None) else ""))
        return 2
    except KeyboardInterrupt:
        _err(f"{name}: interrupted")
        return 130


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
