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
the grid's lags, which makes it too long. :func:`calibrate` removes the mean bias by
simulation: a few multiplicative fixed-point corrections of the targets fed to the closed
form, on the mean over a set of seeds.

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

from roughgp.common.checks import check_nonnegative
from roughgp.common.grid import normalize
from roughgp.metrology import texture, texture_heights
from roughgp.models import surfaces
from roughgp.models.surfaces import GrooveParameters
from roughgp.sampling import diagnostics

__all__ = ["TARGET_NAMES", "MIN_GROOVE_LENGTHS", "RoughnessTargets", "GroundHyperparameters",
           "as_targets", "hyperparameters_for", "predicted_targets", "measure",
           "achieved_parameters", "summarize", "direction_difference", "mean_direction",
           "sq_prediction", "groove_lengths", "field_warning", "Calibration", "calibrate",
           "simulate_with_targets"]

#: The ISO 25178-2 parameters that can be prescribed, in this order.
TARGET_NAMES = ("Sq", "Sal", "Str", "Std")
_RESOLVED = 3.0  # Sal below this many grid spacings is resolved poorly by the ACF's lags
#: Fields shorter than this many lambda_a (along their shorter side) give biased Sal and Str
#: (measured for Sal = 6, Str = 0.1: the mean Sal 5-20 % short below 3 lambda_a, one surface's
#: Sal scattered by 20-40 %, Str undefined on some surfaces below 5 lambda_a).
MIN_GROOVE_LENGTHS = 5.0


def _fold(degrees):
    """A direction in degrees folded to (-90, 90], the convention of texture_direction."""
    return float(90.0 - np.mod(90.0 - degrees, 180.0))


def direction_difference(a, b):
    """``a - b`` for directions in degrees (period 180), folded to (-90, 90]."""
    return 90.0 - np.mod(90.0 - (np.asarray(a, float) - np.asarray(b, float)), 180.0)


def mean_direction(angles):
    """Circular mean of directions in degrees (period 180: the mean of the doubled angles),
    folded to (-90, 90]."""
    doubled = np.exp(2j * np.radians(np.asarray(angles, float)))
    return _fold(math.degrees(np.angle(doubled.mean())) / 2)


def _number(name, value):
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
        values = {name: _number(name, getattr(self, name)) for name in TARGET_NAMES}
        if values["Sq"] <= 0:
            raise ValueError(f"Sq must be > 0 (allowed range: (0, inf)), got {values['Sq']!r}")
        if values["Sal"] <= 0:
            raise ValueError(f"Sal must be > 0 (allowed range: (0, inf)), got "
                             f"{values['Sal']!r}")
        if not 0 < values["Str"] <= 1:
            raise ValueError(f"Str must be in (0, 1] (allowed range: 0 < Str <= 1; 1 is "
                             f"isotropic), got {values['Str']!r}")
        values["Std"] = _fold(values["Std"])
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


def _check_spacing(spacing):
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
            +13 % at 1.5 spacings, +3 % and +5 % at 2; :func:`calibrate` corrects it).

    Returns:
        :class:`GroundHyperparameters` with :math:`\lambda_a \ge \lambda_b`.

    Raises:
        ValueError: naming the parameter and its allowed range.
    """
    noise_variance = _number("noise_variance", noise_variance)
    check_nonnegative("noise_variance", noise_variance)
    spacing = _check_spacing(spacing)
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
    """How many correlation lengths :math:`\lambda_a` (the longer lengthscale) the shorter
    side of the field spans; below :data:`MIN_GROOVE_LENGTHS` the measured Sal and Str are
    biased and Str may be undefined."""
    shape, spacing = normalize(_shape(shape), spacing)
    extent = min(n * d for n, d in zip(shape, spacing))
    return float(extent / max(hyperparameters.lengthscales))


def field_warning(hyperparameters: GroundHyperparameters, shape, spacing=1.0):
    """A message when the field spans fewer than :data:`MIN_GROOVE_LENGTHS` correlation
    lengths :math:`\lambda_a`, else None."""
    n = groove_lengths(hyperparameters, shape, spacing)
    if n >= MIN_GROOVE_LENGTHS:
        return None
    lam = max(hyperparameters.lengthscales)
    return (f"the field spans only {n:.3g} correlation lengths lambda_a = {lam:.4g} along its "
            f"shorter side (fewer than {MIN_GROOVE_LENGTHS:g}): the measured Sal and Str will "
            f"be biased (Sal short) and may be undefined; use a field at least "
            f"{MIN_GROOVE_LENGTHS * lam:.4g} long, or calibrate() for this shape")


# --------------------------------------------------------------------------- calibration

@dataclass(frozen=True)
class Calibration:
    """The result of :func:`calibrate`.

    Attributes:
        targets: the prescribed :class:`RoughnessTargets`.
        shape, spacing, noise_variance: the field and noise it was calibrated for.
        hyperparameters: the calibrated :class:`GroundHyperparameters`.
        closed_form: those of :func:`hyperparameters_for` for the targets themselves.
        history: per round, ``(inputs, means)``: the targets fed to the closed form and the
            mean measured parameters over ``seeds`` (dicts by name); the last entry's inputs
            gave ``hyperparameters``, its means are those the round measured (NaN when the
            last correction was not measured again).
        seeds: the seeds of the surfaces simulated in every round.
    """

    targets: RoughnessTargets
    shape: tuple
    spacing: object
    noise_variance: float
    hyperparameters: GroundHyperparameters
    closed_form: GroundHyperparameters
    history: tuple
    seeds: tuple


def _shape(shape):
    shape = (shape,) if np.ndim(shape) == 0 else tuple(shape)
    if len(shape) != 2:
        raise ValueError(f"shape must be (ny, nx) for a surface, got {shape!r}")
    return normalize(shape)[0]


def calibrate(targets, shape, *, seeds=range(8), iterations=3, noise_variance=1.0,
              spacing=1.0, method="auto", correct=("Sq", "Sal", "Str")) -> Calibration:
    r"""Hyperparameters whose surfaces of ``shape`` hit the targets ON AVERAGE.

    The closed form (:func:`hyperparameters_for`) is exact for an infinite field. On a
    finite one the estimators are biased (module docstring). Starting from the targets
    themselves, each round draws one surface per seed with the hyperparameters of the
    current inputs (eq 18 plus eq 8), measures the mean of each parameter over the seeds,
    and corrects the inputs: multiplicatively for Sq, Sal and Str
    (:math:`T_{in} \leftarrow T_{in}\,T/\bar M`, which scales :math:`\sigma_k^2` and the
    lengthscales :math:`\lambda_b \propto S_{al}`, :math:`\lambda_a \propto S_{al}/S_{tr}`),
    additively for Std (only when named in ``correct``; for a strong lay its mean was found
    within about a degree of the target, pulled slightly toward the grid's axes). Str is
    capped at 1 and Sq kept above the limit :math:`\sqrt{5\sigma^2/4}`.
    The same seeds are used in every round; they give the same white noise only while the
    sampler keeps its circulant torus, so the rounds also differ by the luck of the draw.

    Cost: ``iterations`` rounds of ``len(seeds)`` surfaces. The result hits the targets on
    the mean over THESE seeds, so it is only as precise as that mean: a bias smaller than
    one surface's sd / sqrt(len(seeds)) cannot be corrected. Judge it on other seeds.

    Args:
        targets: :class:`RoughnessTargets` or a mapping with the keys Sq, Sal, Str, Std.
        shape: ``(ny, nx)`` of the surfaces to be drawn.
        seeds: the seeds of each round's surfaces (at least 2).
        iterations: number of corrections (rounds), >= 1.
        noise_variance, spacing: as in :func:`hyperparameters_for`.
        method: the sampler of :func:`roughgp.models.surfaces.ground`.
        correct: which parameters to correct (a subset of Sq, Sal, Str, Std).

    Raises:
        ValueError: bad arguments, or Sal / Str undefined on a surface (the field is too
            short for the grooves: the message says so).
    """
    t = as_targets(targets)
    shape = _shape(shape)
    seeds = tuple(seeds)
    if len(seeds) < 2:
        raise ValueError(f"seeds must name at least 2 seeds, got {seeds!r}")
    if isinstance(iterations, bool) or not isinstance(iterations, (int, np.integer)) \
            or iterations < 1:
        raise ValueError(f"iterations must be an integer >= 1, got {iterations!r}")
    unknown = [c for c in correct if c not in TARGET_NAMES]
    if unknown:
        raise ValueError(f"correct must name parameters among {', '.join(TARGET_NAMES)}, "
                         f"got {', '.join(map(repr, unknown))}")
    noise_variance = _number("noise_variance", noise_variance)
    closed_form = hyperparameters_for(**t.as_dict(), noise_variance=noise_variance,
                                      spacing=spacing)
    inputs = t.as_dict()
    lowest = math.sqrt(5.0 * noise_variance / 4.0)
    history = []
    for _ in range(int(iterations)):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # the resolution warning was given once above
            hyper = hyperparameters_for(**inputs, noise_variance=noise_variance,
                                        spacing=spacing)
        values = achieved_parameters(hyper, shape, seeds=seeds, spacing=spacing,
                                     method=method)
        for name in correct:
            bad = int(np.count_nonzero(np.isnan(values[name])))
            if bad:
                raise ValueError(
                    f"{name} is undefined on {bad} of {len(seeds)} surfaces of shape "
                    f"{shape}: the ACF does not decay to 0.2 within the field (the decay "
                    f"length along the grooves is about Sal/Str = {t.Sal / t.Str:.4g}); "
                    f"use a larger shape, or leave {name} out of correct")
        means = {name: m for name, (m, _) in summarize(values).items()}
        history.append((dict(inputs), means))
        new = dict(inputs)
        if "Sq" in correct:
            new["Sq"] = max(inputs["Sq"] * t.Sq / means["Sq"], lowest * (1 + 1e-9))
        if "Sal" in correct:
            new["Sal"] = inputs["Sal"] * t.Sal / means["Sal"]
        if "Str" in correct:
            new["Str"] = min(1.0, inputs["Str"] * t.Str / means["Str"])
        if "Std" in correct:
            new["Std"] = _fold(inputs["Std"] + float(direction_difference(t.Std, means["Std"])))
        inputs = new
    history.append((dict(inputs), dict.fromkeys(TARGET_NAMES, math.nan)))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        final = hyperparameters_for(**inputs, noise_variance=noise_variance, spacing=spacing)
    return Calibration(targets=t, shape=shape, spacing=spacing, noise_variance=noise_variance,
                       hyperparameters=final, closed_form=closed_form, history=tuple(history),
                       seeds=seeds)


# --------------------------------------------------------------------------- simulating

def simulate_with_targets(targets, shape, *, seed, spacing=1.0, noise_variance=1.0,
                          calibration: Calibration | None = None, method="auto"):
    """A ground surface (eq 18 plus the noise of eq 8, :func:`roughgp.models.surfaces.ground`)
    whose ISO 25178-2 parameters are ``targets`` (Sq 4.1, Sal 4.2.1, Str 4.2.2, Std 4.5.1).

    Args:
        targets: :class:`RoughnessTargets` or a mapping with the keys Sq, Sal, Str, Std.
        shape: ``(ny, nx)``.
        seed: int, None or ``numpy.random.Generator``; the same seed gives the same surface.
        spacing: grid spacing, scalar or ``(dy, dx)``, in the unit of Sal.
        noise_variance: :math:`\\sigma^2` of eq 8 (default 1, the paper's).
        calibration: a :func:`calibrate` result for the same targets, shape, spacing and
            noise variance, whose hyperparameters are used; None: the closed form of
            :func:`hyperparameters_for`, with a ``UserWarning`` when the field spans fewer
            than :data:`MIN_GROOVE_LENGTHS` correlation lengths :math:`\lambda_a`.
        method: the sampler of :func:`roughgp.models.surfaces.ground`.

    Returns:
        ``(z, hyperparameters)``: the surface ``z[iy, ix]`` and the
        :class:`GroundHyperparameters` it was drawn with.
    """
    t = as_targets(targets)
    shape = _shape(shape)
    noise_variance = _number("noise_variance", noise_variance)
    if calibration is None:
        hyper = hyperparameters_for(**t.as_dict(), noise_variance=noise_variance,
                                    spacing=spacing)
    else:
        if not isinstance(calibration, Calibration):
            raise ValueError(f"calibration must be a Calibration from calibrate(), got "
                             f"{type(calibration).__name__}")
        mismatch = [name for name, mine, theirs in (
            ("targets", t, calibration.targets), ("shape", shape, calibration.shape),
            ("noise_variance", noise_variance, calibration.noise_variance),
            ("spacing", tuple(_check_spacing(spacing)),
             tuple(_check_spacing(calibration.spacing)))) if mine != theirs]
        if mismatch:
            raise ValueError(f"calibration was made for other {', '.join(mismatch)}: "
                             f"calibrate for these targets, shape, spacing and noise_variance")
        hyper = calibration.hyperparameters
    if calibration is None:
        message = field_warning(hyper, shape, spacing)
        if message:
            warnings.warn(message, stacklevel=2)
    z = surfaces.ground(shape, **hyper.ground_kwargs(), spacing=spacing, seed=seed,
                        method=method)
    return z, hyper
