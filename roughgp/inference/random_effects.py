r"""A hierarchy over regions: the regions' eq 18 parameters scattered around a population
(beyond the paper; issue 40, item 3: the "hierarchical GPs [36]" of section 4).

Each region (a tile of one map, or one of several measurements of a part) gives an estimate
:math:`\hat\theta_i` of a parameter with its own variance :math:`v_i`
(:mod:`roughgp.inference.tile_fit`). The normal random-effects model

.. math::
    \hat\theta_i \mid \theta_i \sim N(\theta_i, v_i), \qquad \theta_i \sim N(\mu, \tau^2)

has the population mean :math:`\mu` and the spread between regions :math:`\tau`, estimated by
DerSimonian and Laird's moments (1986): :math:`Q = \sum_i w_i(\hat\theta_i - \bar\theta_w)^2`
with :math:`w_i = 1/v_i`, :math:`\hat\tau^2 = \max\{0, (Q - (k-1)) / (\sum w_i - \sum w_i^2 /
\sum w_i)\}`; :math:`Q \sim \chi^2_{k-1}` when the regions share one value (:math:`\tau = 0`:
a stationary surface), its p value is the test of homogeneity. Each region's value is then
shrunk towards the population by its precision (the best linear unbiased predictor),

.. math::
    \theta_i^* = \hat\mu + \frac{\hat\tau^2}{\hat\tau^2 + v_i}(\hat\theta_i - \hat\mu),\qquad
    \operatorname{Var}\theta_i^* \approx \frac{\hat\tau^2 v_i}{\hat\tau^2 + v_i}
    + \Big(\frac{v_i}{\hat\tau^2 + v_i}\Big)^2 \operatorname{Var}\hat\mu,

so a region whose difference is within its noise keeps the population's value. The spread is
kept only where Cochran's test rejects one value at ``spread_level`` (1 %; the moment
estimate alone is above 0 in about half of the sets of regions that share one value), so a
stationary map comes back stationary in about 99 % of the parameters. Given the regions'
positions, the population's value may be a plane in position (a meta-regression: Raudenbush's
moments for :math:`\tau^2` about it), kept only when a Wald test rejects the constant at
``trend_level`` (1 %): a roughness gradient or a turning lay is then shrunk towards the plane,
not towards one value, which would pull the outer regions in. Or the population's value may
step between two zones: one value on each side of a boundary midway between two columns (or
rows) of regions, kept when its Wald test, Bonferroni-adjusted over the candidate boundaries,
rejects the constant at ``trend_level``. Where the plane's test rejects, the plane along x,
along y or along both, and the step where its test rejects, compete by :math:`Q + 2p`
(Akaike's criterion of the weighted fit, :math:`p` coefficients): the smallest is kept.
An angle (the lay, period pi) is pooled as its difference from the regions' weighted mean
direction.

**The reported uncertainty.** The variance above treats :math:`\hat\tau` and the chosen form
(constant, plane or step) as known, and the tests may have set :math:`\hat\tau` to 0. With 16
regions neither is known: a spread between regions smaller than their noise, or a gradient
over four columns of noisy regions that a step fits as well, puts the truth outside two such
standard errors at many more regions than 5 % (``tests/inference/test_random_effects.py``
measures it). The reported standard error is therefore the root posterior mean squared error
of :math:`\theta_i^*`, :math:`\text{sd}_i^2 = \operatorname{Var}(\theta_i \mid \hat\theta) +
(\theta_i^* - \operatorname{E}(\theta_i \mid \hat\theta))^2`, with :math:`\tau` integrated out
and the forms averaged (:mod:`roughgp.inference.pooled_errors`). The values themselves stay the
plug-in :math:`\theta_i^*` (a stationary map still comes back stationary); their errors are
what a reader of the fields needs. Where no form's posterior is proper (fewer than two regions
more than its coefficients) the plug-in variance is kept.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import scipy.stats

from roughgp.inference.pooled_errors import averaged_moments

__all__ = ["Pooled", "pool", "wrap_angle"]



def wrap_angle(angle):
    """An angle (period pi: a lay) in ``[-pi/2, pi/2)``."""
    return (np.asarray(angle, dtype=np.float64) + math.pi / 2) % math.pi - math.pi / 2


@dataclass(frozen=True)
class Pooled:
    """One parameter pooled over ``k`` regions (:func:`pool`).

    Attributes:
        mean: :math:`\\hat\\mu` (with a trend: its value at the regions' mean position);
            mean_sd: its standard error.
        tau: :math:`\\hat\\tau`, the spread between regions about the population (or about
            the trend): 0 when one value (or one plane) fits all.
        q, p_homogeneity: Cochran's Q about the constant and its chi-squared p value (k - 1
            degrees of freedom): the test that the regions share one value.
        slope, p_trend: the trend's gradient per unit length ``(d/dx, d/dy)`` (zeros when no
            trend is kept) and the Wald test's p value of a plane over a constant (NaN when no
            positions were given or too few regions).
        shrunk, shrunk_sd: each region's :math:`\theta_i^*` and its standard error, the
            root posterior mean squared error with :math:`\tau` integrated out (module
            docstring; the population's value and spread for a region without an estimate).
        plugin_sd: the standard error that takes :math:`\\hat\\tau` as known (the formula
            above), for comparison.
        n_regions: the regions with an estimate.
        step, p_step: ``(axis, boundary)`` (``"x"`` or ``"y"``, the position between two
            columns or rows of regions) where the population's value steps between two
            zones, ``()`` when no step is kept; the Bonferroni-adjusted p value of the best
            step's Wald test over a constant (NaN without positions or candidates).
    """

    mean: float
    mean_sd: float
    tau: float
    q: float
    p_homogeneity: float
    slope: tuple
    p_trend: float
    shrunk: np.ndarray
    shrunk_sd: np.ndarray
    plugin_sd: np.ndarray
    n_regions: int
    step: tuple = ()
    p_step: float = math.nan


def _moments(t, v, design, level=None):
    """DerSimonian-Laird's moment estimate of tau^2 about the weighted least-squares fit of
    ``design`` (Raudenbush's meta-regression form), then the coefficients with weights
    1 / (v + tau^2) and their covariance. With ``level``, tau^2 is 0 unless the residual Q
    test rejects at that level."""
    w = 1.0 / v
    xtw = design.T * w
    inverse = np.linalg.inv(xtw @ design)
    residual = t - design @ (inverse @ (xtw @ t))
    q = float(np.sum(w * residual**2))
    trace = float(np.sum(w) - np.trace(inverse @ (design.T * w**2) @ design))
    df = t.size - design.shape[1]
    tau2 = max(0.0, (q - df) / trace) if trace > 0 else 0.0
    if level is not None and (df < 1 or scipy.stats.chi2.sf(q, df) >= level):
        tau2 = 0.0
    w_star = 1.0 / (v + tau2)
    xtw = design.T * w_star
    covariance = np.linalg.inv(xtw @ design)
    return tau2, covariance @ (xtw @ t), covariance, q


def pool(estimates, variances, *, angle=False, positions=None, trend_level=0.01,
         spread_level=0.01) -> Pooled:
    """Pool one parameter's regional ``estimates`` with their ``variances`` (module docstring).

    Args:
        estimates, variances: arrays of one shape (the regions); NaN or a non-positive variance
            marks a region without an estimate.
        angle: the parameter is a lay angle in radians (period pi).
        positions: optional ``(..., 2)`` array of the regions' centres ``(x, y)``: the
            population's value may then be a plane in position (a gradient across the part),
            kept when its Wald test rejects a constant at ``trend_level``, or a step between
            two zones (module docstring); the regions then scatter about the plane or the
            zones' values and are shrunk towards them.
        trend_level: the level of the tests of a trend and of a step, in (0, 1).
        spread_level: the level of the test of a spread about the population (or the
            trend), in (0, 1): tau is set to 0, and every region shrunk to the population, unless
            Cochran's Q rejects one value at this level (the moment estimate alone is above 0
            in about half of the sets of regions that share one value); None: no test, tau
            the moment estimate itself (a prediction for a new region wants it).

    Raises ValueError when fewer than two regions have an estimate.
    """
    theta = np.asarray(estimates, dtype=np.float64)
    v = np.asarray(variances, dtype=np.float64)
    if theta.shape != v.shape:
        raise ValueError(f"estimates and variances must have one shape, got {theta.shape} "
                         f"and {v.shape}")
    for name, level in (("trend_level", trend_level), ("spread_level", spread_level)):
        if level is None and name == "spread_level":
            continue
        if not 0 < level < 1:
            raise ValueError(f"{name} must be in (0, 1), got {level!r}")
    known = np.isfinite(theta) & np.isfinite(v) & (v > 0)
    k = int(known.sum())
    if k < 2:
        raise ValueError(f"pooling needs at least 2 regions with an estimate and a positive "
                         f"variance, got {k}")
    w = np.where(known, 1.0 / np.where(known, v, 1.0), 0.0)
    reference = 0.0
    if angle:
        doubled = 2 * np.where(known, theta, 0.0)
        reference = 0.5 * math.atan2(float(np.sum(w * np.sin(doubled))),
                                     float(np.sum(w * np.cos(doubled))))
        theta = wrap_angle(theta - reference)
    t, vk = theta[known], v[known]
    design = np.ones((theta.shape + (1,)))
    tau2, beta, covariance, q = _moments(t, vk, design[known], spread_level)
    p_homogeneity = float(scipy.stats.chi2.sf(q, k - 1))
    slope, p_trend = (0.0, 0.0), math.nan
    step, p_step = (), math.nan
    forms = [design]        # every form the population's value might take, for the errors
    if positions is not None:
        xy = np.asarray(positions, dtype=np.float64)
        if xy.shape != theta.shape + (2,):
            raise ValueError(f"positions must have shape {theta.shape + (2,)}, got {xy.shape}")
        centre = xy[known].mean(axis=0)
        varying = [c for c in range(2) if np.ptp(xy[known][:, c]) > 0]
        kept = []       # (criterion, design, tau2, beta, covariance, slope, step)
        if varying and k >= len(varying) + 3:
            plane = np.concatenate([np.ones(theta.shape + (1,)),
                                    (xy - centre)[..., varying]], axis=-1)
            p_trend, _ = _against_constant(t, vk, plane[known], spread_level)
            for axes in ([[c] for c in varying] + ([varying] if len(varying) > 1 else [])):
                plane = np.concatenate([np.ones(theta.shape + (1,)),
                                        (xy - centre)[..., axes]], axis=-1)
                forms.append(plane)
                if p_trend < trend_level:       # the plane along x, y or both competes
                    fit = _moments(t, vk, plane[known], spread_level)
                    gradient = [0.0, 0.0]
                    for index, axis in enumerate(axes):
                        gradient[axis] = float(fit[1][1 + index])
                    kept.append((fit[3] + 2 * plane.shape[-1], plane, *fit[:3],
                                 tuple(gradient), ()))
        steps = _step_designs(xy, known, varying)
        forms += [d for d, _ in steps]
        if steps:
            tests = [(_against_constant(t, vk, d[known], spread_level), d, where)
                     for d, where in steps]
            (p_best, fit), d, where = min(tests, key=lambda test: test[0][0])
            p_step = min(1.0, p_best * len(steps))      # Bonferroni over the candidates
            if p_step < trend_level:
                kept.append((fit[3] + 2 * d.shape[-1], d, *fit[:3], (0.0, 0.0), where))
        if kept:
            _, design, tau2, beta, covariance, slope, step = min(kept, key=lambda c: c[0])
    fitted = design @ beta
    fitted_var = np.einsum("...i,ij,...j->...", design, covariance, design)
    vv = np.where(known, v, 1.0)
    shrink = np.where(known, tau2 / (tau2 + vv), 0.0)
    shrunk = fitted + shrink * (np.where(known, theta, fitted) - fitted)
    rest = np.where(known, vv / (tau2 + vv), 1.0)
    plugin_var = np.where(known, shrink * vv, tau2) + rest**2 * fitted_var
    moments = averaged_moments(np.where(known, theta, np.nan), np.where(known, v, np.nan),
                               forms)
    if moments is None:
        shrunk_var = plugin_var
    else:
        posterior_mean, posterior_var = moments
        shrunk_var = posterior_var + (shrunk - posterior_mean) ** 2
    mean, mean_var = float(beta[0]), float(covariance[0, 0])
    if angle:
        shrunk = wrap_angle(shrunk + reference)
        mean = float(wrap_angle(mean + reference))
    return Pooled(mean, math.sqrt(mean_var), math.sqrt(tau2), q, p_homogeneity, slope, p_trend,
                  shrunk, np.sqrt(shrunk_var), np.sqrt(plugin_var), k, step, p_step)


def _against_constant(t, v, design, spread_level):
    """The Wald test's p value of ``design``'s coefficients but the first (the constant) and
    the fit about ``design``: ``(p, (tau2, beta, covariance, q))``, ``q`` the residual Q."""
    tau2, beta, covariance, q = _moments(t, v, design, spread_level)
    b, c = beta[1:], covariance[1:, 1:]
    p = float(scipy.stats.chi2.sf(float(b @ np.linalg.solve(c, b)), b.size))
    return p, (tau2, beta, covariance, q)


def _step_designs(xy, known, varying):
    """The designs of a step between two zones: a constant plus an indicator of the regions
    beyond a boundary midway between two neighbouring columns (``x``) or rows (``y``) of
    regions, at least two regions with an estimate on each side; ``[(design, (axis,
    boundary)), ...]``."""
    designs = []
    for axis in varying:
        coordinate = xy[..., axis]
        levels = np.unique(coordinate[known])
        for boundary in (levels[:-1] + levels[1:]) / 2:
            beyond = coordinate > boundary
            if min(int(np.sum(beyond & known)), int(np.sum(~beyond & known))) < 2:
                continue
            design = np.stack([np.ones(coordinate.shape), beyond.astype(np.float64)], axis=-1)
            designs.append((design, ("xy"[axis], float(boundary))))
    return designs
