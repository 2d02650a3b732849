r"""Ground surfaces with prescribed ISO 25178-2 roughness parameters (beyond the paper).

The paper's conclusion names, as future work [16], to "simulate rough surfaces with
predefined roughness parameters". For the ground surface of section 3.1 -- the GP of eq 18
seen through the Gaussian noise of eq 8 (eq 9) -- four ISO 25178-2:2012 parameters fix the
five hyperparameters up to the choice of the noise variance:

* root mean square height ``Sq`` (4.1), in the height unit;
* autocorrelation length ``Sal`` (4.2.1) and texture aspect ratio ``Str`` (4.2.2), both read
  off the normalised autocorrelation function (ACF) at the threshold :math:`s = 0.2`;
* texture direction ``Std`` (4.5.1), in degrees, the direction of the lay as
  :func:`roughgp.metrology.texture.texture_direction` reports it: counter-clockwise from the x-axis,
  folded to (-90, 90].

**The forward map** (an infinite field). The surface heights have the ACVF
:math:`r_E(\boldsymbol\tau) + \sigma^2\delta_{\boldsymbol\tau 0}` (eq 18 plus eq 8), so
:math:`S_q^2 = \sigma_k^2 + \sigma^2` and, off zero lag, the ACF is
:math:`\rho(\boldsymbol\tau) = c\,\exp(-\lVert\boldsymbol\Lambda^{-1}\mathbf T_\phi
\boldsymbol\tau\rVert)` with :math:`c = \sigma_k^2/(\sigma_k^2+\sigma^2)`. Its 0.2 contour
is the ellipse :math:`\lVert\boldsymbol\Lambda^{-1}\mathbf T_\phi\boldsymbol\tau\rVert =
\ln(5c)` with half-axes :math:`\lambda_a\ln(5c)` along the grooves and
:math:`\lambda_b\ln(5c)` across them, hence (for :math:`\lambda_a \ge \lambda_b`)

.. math::
    S_q = \sqrt{\sigma_k^2+\sigma^2},\quad
    S_{al} = \lambda_b \ln\frac{5\sigma_k^2}{\sigma_k^2+\sigma^2},\quad
    S_{tr} = \frac{\lambda_b}{\lambda_a},\quad S_{td} = \phi .

**The inverse** (:func:`hyperparameters_for`), in closed form:

.. math::
    \sigma_k^2 = S_q^2 - \sigma^2,\quad
    \lambda_b = S_{al} \Big/ \ln\frac{5(S_q^2-\sigma^2)}{S_q^2},\quad
    \lambda_a = \lambda_b / S_{tr},\quad \phi = S_{td}.

It exists exactly when :math:`5(S_q^2 - \sigma^2) > S_q^2`, i.e.
:math:`S_q > \tfrac{\sqrt5}{2}\sigma \approx 1.118\,\sigma` (then also
:math:`\sigma_k^2 > 0`; with :math:`\sigma^2 = 0` it is :math:`S_q > 0`): the ACF just off
zero lag, :math:`c`, must start above 0.2, or it never decays to 0.2 and Sal does not exist;
further :math:`S_{al} > 0`, :math:`0 < S_{tr} \le 1` and any finite :math:`S_{td}`.
Near the limit (:math:`5c` close to 1) Sal is very sensitive to the ACF: its slope at the
crossing is :math:`0.2/\lambda_b` with :math:`\lambda_b = S_{al}/\ln(5c)` large.

**A finite field and a finite grid** bias the estimators: removing the mean lowers Sq (by
:math:`\operatorname{Var}(\bar z)`, :func:`sq_prediction`) and the whole empirical ACF;
Sal is a minimum and the longest decay length a maximum over many noisy directions; a
field only a few :math:`\lambda_a` long holds few independent grooves (and Str may not be
defined on it); and a Sal of a few grid spacings is read off an ACF interpolated between
the grid's lags, which makes it too long. :func:`roughgp.targets.calibration.calibrate`
removes the mean bias by simulation: a few multiplicative fixed-point corrections of the
targets fed to the closed form, on the mean over a set of seeds.

This module holds the closed form both ways and the measuring of drawn surfaces;
:mod:`roughgp.targets.calibration` calibrates the closed form on a finite field and draws
surfaces with prescribed parameters (:func:`~roughgp.targets.calibration.simulate_with_targets`).

Units: lengths in the unit of ``spacing`` (the CLI: um), heights in that of ``Sq``, angles
in degrees for ``Std`` and radians for the hyperparameter ``angle`` (as in
:mod:`roughgp.models.surfaces`).
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from roughgp.common.checks import check_nonnegative, check_scale
from roughgp.common.grid import normalize
from roughgp.metrology import texture, texture_heights
from roughgp.models import surfaces
from roughgp.models.surfaces import GrooveParameters
from roughgp.sampling import diagnostics

__all__ = ["TARGET_NAMES", "MIN_GROOVE_LENGTHS", "RoughnessTargets", "GroundHyperparameters",
           "as_targets", "hyperparameters_for", "predicted_targets", "measure",
           "achieved_parameters", "summarize", "direction_difference", "mean_direction",
           "fold_direction", "finite_number", "check_spacing", "surface_shape",
           "sq_prediction", "groove_lengths", "field_warning"]

#: The ISO 25178-2 parameters that can be prescribed, in this order.
TARGET_NAMES = ("Sq", "Sal", "Str", "Std")
_RESOLVED = 3.0  # Sal below this many grid spacings is resolved poorly by the ACF's lags
#: Fields shorter than this many lambda_a (along their shorter side) give biased Sal and Str
#: (measured for Sal = 6, Str = 0.1: the mean Sal 5-20 % short below 3 lambda_a, one surface's
#: Sal scattered by 20-40 %, Str undefined on some surfaces below 5 lambda_a).
MIN_GROOVE_LENGTHS = 5.0


def fold_direction(degrees):
    """A direction in degrees folded to (-90, 90], the convention of texture_direction."""
    return float(90.0 - np.mod(90.0 - degrees, 180.0))


def direction_difference(a, b):
    """``a - b`` for directions in degrees (period 180), folded to (-90, 90]."""
    return 90.0 - np.mod(90.0 - (np.asarray(a, float) - np.asarray(b, float)), 180.0)


def mean_direction(angles):
    """Circular mean of directions in degrees (period 180: the mean of the doubled angles),
    folded to (-90, 90]."""
    doubled = np.exp(2j * np.radians(np.asarray(angles, float)))
    return fold_direction(math.degrees(np.angle(doubled.mean())) / 2)


def finite_number(name, value):
    """``value`` as a finite float; errors name ``name``."""
    try:
        value = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a number, got {value!r}") from None
    if not math.isfinite(value):
        raise ValueError(f"{name} must be finite (no NaN or inf), got {value!r}")
    return value


@dataclass(frozen=True)
class RoughnessTargets:
    """Prescribed ISO 25178-2:2012 parameters of a ground surface.

    Attributes:
        Sq: root mean square height (4.1), > 0, in the height unit.
        Sal: autocorrelation length (4.2.1, s = 0.2), > 0, in the unit of the spacing.
        Str: texture aspect ratio (4.2.2), in (0, 1].
        Std: texture direction (4.5.1), degrees counter-clockwise from x; any finite angle,
            stored folded to (-90, 90] as :func:`roughgp.metrology.texture.texture_direction` reports it.
    """

    Sq: float
    Sal: float
    Str: float
    Std: float

    def __post_init__(self):
        values = {name: finite_number(name, getattr(self, name)) for name in TARGET_NAMES}
        for name in ("Sq", "Sal"):
            check_scale(name, values[name])
        if not 0 < values["Str"] <= 1:
            raise ValueError(f"Str must be in (0, 1] (allowed range: 0 < Str <= 1; 1 is "
                             f"isotropic), got {values['Str']!r}")
        values["Std"] = fold_direction(values["Std"])
        for name, value in values.items():
            object.__setattr__(self, name, value)

    def as_dict(self) -> dict:
        return {name: getattr(self, name) for name in TARGET_NAMES}


def as_targets(targets) -> RoughnessTargets:
    """:class:`RoughnessTargets` from itself or a mapping with exactly the keys Sq, Sal, Str
    and Std; a ``ValueError`` names a missing or unknown key."""
    if isinstance(targets, RoughnessTargets):
        return targets
    if not isinstance(targets, Mapping):
        raise ValueError(f"targets must be RoughnessTargets or a mapping with the keys "
                         f"{', '.join(TARGET_NAMES)}, got {type(targets).__name__}")
    unknown = [k for k in targets if k not in TARGET_NAMES]
    missing = [k for k in TARGET_NAMES if k not in targets]
    if unknown:
        raise ValueError(f"unknown target {', '.join(map(repr, unknown))}: the targets are "
                         f"{', '.join(TARGET_NAMES)}")
    if missing:
        raise ValueError(f"missing target {', '.join(missing)}: all of "
                         f"{', '.join(TARGET_NAMES)} are required")
    return RoughnessTargets(**{k: targets[k] for k in TARGET_NAMES})


@dataclass(frozen=True)
class GroundHyperparameters:
    """Hyperparameters of a ground surface: eq 18 (``variance`` :math:`\\sigma_k^2`,
    ``lengthscales`` :math:`(\\lambda_a, \\lambda_b)`, ``angle`` :math:`\\phi` in radians)
    and the noise variance :math:`\\sigma^2` of eq 8."""

    variance: float
    lengthscales: tuple
    angle: float
    noise_variance: float

    @property
    def groove(self) -> GrooveParameters:
        """The eq 18 part, as :class:`roughgp.models.surfaces.GrooveParameters`."""
        return GrooveParameters(self.variance, tuple(self.lengthscales), self.angle)

    def kernel(self):
        """The eq 18 kernel (without the noise)."""
        return self.groove.kernel()

    def ground_kwargs(self) -> dict:
        """Keyword arguments of :func:`roughgp.models.surfaces.ground` (noise included)."""
        return {"variance": self.variance, "lengthscales": tuple(self.lengthscales),
                "angle": self.angle, "noise_variance": self.noise_variance}


def check_spacing(spacing):
    """``spacing`` (scalar or ``(dy, dx)``) as the ``(dy, dx)`` of a surface, checked."""
    _, spacing = normalize((1, 1), spacing)
    return spacing


def hyperparameters_for(Sq, Sal, Str, Std, *, noise_variance=1.0,
                        spacing=1.0) -> GroundHyperparameters:
    r"""Hyperparameters of eq 18 and eq 8 whose surface has the given ISO 25178-2 parameters.

    The closed-form inversion of the module docstring (an infinite field):
    :math:`\sigma_k^2 = S_q^2-\sigma^2`,
    :math:`\lambda_b = S_{al}/\ln(5(S_q^2-\sigma^2)/S_q^2)`, :math:`\lambda_a =
    \lambda_b/S_{tr}` and :math:`\phi = S_{td}` (folded to (-90, 90] degrees, then radians).

    Args:
        Sq: root mean square height (ISO 25178-2 4.1); must exceed
            :math:`\sqrt{5\sigma^2/4}` so that the ACF off zero lag,
            :math:`\sigma_k^2/(\sigma_k^2+\sigma^2)`, starts above 0.2 (and > 0).
        Sal: autocorrelation length (4.2.1), > 0, in the unit of ``spacing``.
        Str: texture aspect ratio (4.2.2), in (0, 1].
        Std: texture direction (4.5.1), degrees; any finite angle (period 180).
        noise_variance: :math:`\sigma^2 \ge 0` of eq 8 (default 1, the paper's and that of
            :func:`roughgp.models.surfaces.ground`); it must be below :math:`0.8\,S_q^2`.
        spacing: the grid spacing (scalar or ``(dy, dx)``) the surface will be drawn on: not
            used by the formula, only to warn (``UserWarning``) when Sal is under three
            spacings. There the ACF, interpolated between the grid's lags, is resolved
            poorly and the measured Sal and Str come out long (measured: about +9 % and
            +13 % at 1.5 spacings, +3 % and +5 % at 2;
            :func:`~roughgp.targets.calibration.calibrate` corrects it).

    Returns:
        :class:`GroundHyperparameters` with :math:`\lambda_a \ge \lambda_b`.

    Raises:
        ValueError: naming the parameter and its allowed range.
    """
    noise_variance = finite_number("noise_variance", noise_variance)
    check_nonnegative("noise_variance", noise_variance)
    spacing = check_spacing(spacing)
    t = RoughnessTargets(Sq, Sal, Str, Std)  # finite, Sq > 0, Sal > 0, 0 < Str <= 1
    lowest = math.sqrt(5.0 * noise_variance / 4.0)
    if t.Sq <= lowest:
        raise ValueError(
            f"Sq must be > sqrt(5 noise_variance / 4) = {lowest:.6g} for noise_variance = "
            f"{noise_variance:g} (allowed range: ({lowest:.6g}, inf)), got {t.Sq!r}: the ACF "
            f"of eq 18 plus noise starts at sigma_k^2 / Sq^2 = (Sq^2 - noise_variance) / Sq^2 "
            f"off zero lag and must start above s = 0.2 to decay to it (Sal); lower "
            f"noise_variance below 0.8 Sq^2 = {0.8 * t.Sq ** 2:.6g} or raise Sq")
    variance = t.Sq ** 2 - noise_variance
    factor = math.log(5.0 * variance / t.Sq ** 2)
    lambda_b = t.Sal / factor
    if t.Sal < _RESOLVED * float(spacing.max()):
        warnings.warn(f"Sal = {t.Sal:g} is under {_RESOLVED:g} grid spacings "
                      f"({float(spacing.max()):g}): the ACF's lags resolve it poorly and the "
                      f"measured Sal and Str come out several percent long (calibrate() "
                      f"corrects that)", stacklevel=2)
    return GroundHyperparameters(variance=variance, lengthscales=(lambda_b / t.Str, lambda_b),
                                 angle=math.radians(t.Std), noise_variance=noise_variance)


def predicted_targets(hyperparameters: GroundHyperparameters) -> RoughnessTargets:
    r"""The forward closed form: the ISO 25178-2 parameters of an infinite field,
    :math:`S_q = \sqrt{\sigma_k^2+\sigma^2}`, :math:`S_{al} = \min(\lambda)\ln(5c)`,
    :math:`S_{tr} = \min(\lambda)/\max(\lambda)` and :math:`S_{td}` the direction of the
    longer lengthscale, with :math:`c = \sigma_k^2/(\sigma_k^2+\sigma^2)` (eq 18, eq 8).
    A ``ValueError`` when :math:`5c \le 1` (the ACF never reaches 0.2: no Sal)."""
    h = hyperparameters
    lambda_a, lambda_b = (float(v) for v in h.lengthscales)
    sq2 = h.variance + h.noise_variance
    if not (h.variance > 0 and 5 * h.variance > sq2):
        raise ValueError(f"the ACF of these hyperparameters starts at sigma_k^2 / (sigma_k^2 + "
                         f"sigma^2) = {h.variance / sq2:.4g} <= 0.2 off zero lag: Sal and "
                         f"Str are undefined (variance must be > noise_variance / 4)")
    factor = math.log(5 * h.variance / sq2)
    direction = math.degrees(h.angle) + (0.0 if lambda_a >= lambda_b else 90.0)
    return RoughnessTargets(Sq=math.sqrt(sq2), Sal=min(lambda_a, lambda_b) * factor,
                            Str=min(lambda_a, lambda_b) / max(lambda_a, lambda_b),
                            Std=direction)


def surface_shape(shape):
    """``shape`` as the ``(ny, nx)`` of a surface (an int gives a square)."""
    shape = (shape,) if np.ndim(shape) == 0 else tuple(shape)
    if len(shape) != 2:
        raise ValueError(f"shape must be (ny, nx) for a surface, got {shape!r}")
    return normalize(shape)[0]


# --------------------------------------------------------------------------- measuring

def measure(z, spacing=1.0) -> dict:
    """Sq, Sal, Str and Std of a surface (:mod:`roughgp.metrology.texture`, heights referred to the
    mean); Sal and Str are NaN where the ACF does not decay to 0.2 within the field."""
    z = np.asarray(z, dtype=np.float64)
    out = {"Sq": texture_heights.height_parameters(z)["Sq"]}
    out.update(texture.spatial_parameters(z, spacing, undefined="nan"))
    out["Std"] = texture.texture_direction(z, spacing, undefined="nan")
    return out


def achieved_parameters(hyperparameters: GroundHyperparameters, shape, *, seeds,
                        spacing=1.0, method="auto") -> dict:
    """Draw one surface per seed (:func:`roughgp.models.surfaces.ground`) and :func:`measure` it.

    Returns:
        dict name -> array of shape (len(seeds),), for Sq, Sal, Str, Std.
    """
    seeds = list(seeds)
    if not seeds:
        raise ValueError("seeds must name at least one seed")
    rows = [measure(surfaces.ground(shape, **hyperparameters.ground_kwargs(), spacing=spacing,
                                    seed=seed, method=method), spacing) for seed in seeds]
    return {name: np.array([r[name] for r in rows]) for name in TARGET_NAMES}


def summarize(values: Mapping) -> dict:
    """name -> (mean, sd over the draws) of :func:`achieved_parameters`'s values; Std's mean
    is circular (period 180) and its sd that of the differences from it. NaNs propagate."""
    out = {}
    for name in TARGET_NAMES:
        v = np.asarray(values[name], float)
        sd = lambda x: float(np.std(x, ddof=1)) if x.size > 1 else math.nan  # noqa: E731
        if name == "Std":
            if np.any(np.isnan(v)):
                out[name] = (math.nan, math.nan)
                continue
            centre = mean_direction(v)
            out[name] = (centre, sd(direction_difference(v, centre)))
        else:
            out[name] = (float(np.mean(v)), sd(v))
    return out


def sq_prediction(hyperparameters: GroundHyperparameters, shape, spacing=1.0):
    r"""Mean and standard deviation of the measured Sq of one surface of ``shape``.

    :math:`E[S_q^2] \approx \sigma_k^2 + \sigma^2 - \operatorname{Var}(\bar z)` (the mean is
    removed; :func:`roughgp.sampling.diagnostics.grid_mean_variance`), and by the delta method
    :math:`\operatorname{sd}(S_q) \approx \operatorname{sd}(\hat\sigma_z^2)/(2 S_q)`
    (:func:`roughgp.sampling.diagnostics.sample_variance_sd`).

    Returns:
        ``(mean, sd)``.
    """
    kernel, noise = hyperparameters.kernel(), hyperparameters.noise_variance
    total = hyperparameters.variance + noise
    mean = math.sqrt(total - diagnostics.grid_mean_variance(kernel, shape, spacing, noise))
    sd = diagnostics.sample_variance_sd(kernel, shape, spacing, noise) / (2 * mean)
    return mean, sd


def groove_lengths(hyperparameters: GroundHyperparameters, shape, spacing=1.0) -> float:
    r"""How many correlation lengths :math:`\lambda_a` (the longer lengthscale) the shorter
    side of the field spans; below :data:`MIN_GROOVE_LENGTHS` the measured Sal and Str are
    biased and Str may be undefined."""
    shape, spacing = normalize(surface_shape(shape), spacing)
    extent = min(n * d for n, d in zip(shape, spacing))
    return float(extent / max(hyperparameters.lengthscales))


def field_warning(hyperparameters: GroundHyperparameters, shape, spacing=1.0):
    r"""A message when the field spans fewer than :data:`MIN_GROOVE_LENGTHS` correlation
    lengths :math:`\lambda_a`, else None."""
    n = groove_lengths(hyperparameters, shape, spacing)
    if n >= MIN_GROOVE_LENGTHS:
        return None
    lam = max(hyperparameters.lengthscales)
    return (f"the field spans only {n:.3g} correlation lengths lambda_a = {lam:.4g} along its "
            f"shorter side (fewer than {MIN_GROOVE_LENGTHS:g}): the measured Sal and Str will "
            f"be biased (Sal short) and may be undefined; use a field at least "
            f"{MIN_GROOVE_LENGTHS * lam:.4g} long, or calibrate() for this shape")
