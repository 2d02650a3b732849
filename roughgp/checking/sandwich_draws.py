r"""Predictive simulations without refits: eq 18's parameters drawn from the Whittle fit's
large-sample distribution (beyond the paper; issue 40, item 2).

:mod:`roughgp.checking.predictive` carries the fit's uncertainty into the simulations by a
parametric bootstrap: B measurements drawn from :math:`\hat\theta` and each refitted. At
256 x 256 points a Whittle refit takes half a minute, so B refits per check cost minutes.
The debiased Whittle estimate :math:`\hat u` (:func:`~roughgp.inference.whittle_fit.fit_whittle`,
:math:`u = (\log\sigma_f^2, \log\lambda_a, \log\lambda_b, \phi, \log\sigma^2)`) is
asymptotically normal around the truth with the sandwich (Godambe) covariance
:math:`\Sigma = H^{-1} J H^{-1}` (:func:`~roughgp.inference.whittle_fit.robust_covariance`;
Sykulski et al. 2019, section 4; Guillaumin et al. 2022). Drawing
:math:`u^*_i \sim N(\hat u, \Sigma)` and simulation :math:`i` from :math:`u^*_i` is the
normal approximation of the posterior predictive distribution under a flat prior on
:math:`u` (Gelman et al. 2013, section 4.1): its cost is the :math:`J`'s score draws
(one gradient each), not B fits.

A coordinate whose standard error exceeds :data:`UNDETERMINED_SD` (a factor of 10 per standard
error for the log scales, 45 degrees for the lay) is one the map does not determine (typically
a noise variance at its lower bound, 1e-8 of the surface's): the lay or the noise is held at
the fit (the variance or a length is refused, below) and the
others are drawn from their marginal distribution (the covariance's other rows and columns);
where the information is singular there (the fit's observed information, or the expected
information of a model file), the other coordinates' covariance is that of the information
over them alone (:func:`~roughgp.inference.whittle_fit.held_inverse`). The draws say which were
held. Each other coordinate of :math:`u^*` is held within 3 standard
errors of :math:`\hat u` (beyond the map's side it says little of a length, and drawing one
there means a huge torus), so a
parameter the map barely determines cannot draw absurd surfaces.

Where the map determines the variance or a length only within a factor of 2 per standard
error (:data:`POWERLESS_SD`, the log's standard error), or not at all, drawing is refused
(holding such a parameter at the fit would make the draws look certain where the fit is not;
the same AFM measurement in two formats, ``di-3.di`` and ``matrix-3.txt``, had its variance and
lengths held in one and refused in the other before): the draws within 3 standard errors
would span a factor of 64 or more, from surfaces near white noise to
planes, and a check against such simulations cannot say no (the left halves of two AFM maps
of ``data/``, 0.5 and 0.6 um wide with lengths near the field's side: lengths drawn from
0.001 to 2.4 um). A length is drawn no longer than the fitted model's own or the map's
longer side, whichever is longer: the fit was drawn on that grid
(:func:`~roughgp.surface_models.in_range.keep_in_range`), while a length near
:data:`~roughgp.inference.whittle_fit.FAR_BEYOND` times the side may not embed on any torus
the sampler tries. What this buys out of
sample, against the plug-in simulations, is measured at 256 x 256 in
``benchmarks/held_out_calibration.py`` (``--shape 256 512 --likelihood whittle``).
"""

from __future__ import annotations

import dataclasses
import math
from typing import NamedTuple

import numpy as np

from roughgp.common.checks import as_generator, check_integer
from roughgp.inference.whittle_fit import (
    UNDETERMINED_SE,
    WhittleFit,
    implied_fit,
    robust_covariance,
)
from roughgp.models.surfaces import GrooveParameters
from roughgp.surface_models.coordinates import eq18_coordinates
from roughgp.surface_models.model import FittedModel

__all__ = ["MAX_SANDWICH_MODELS", "CLIP_SD", "UNDETERMINED_SD", "POWERLESS_SD",
           "SandwichDraws", "sandwich_models"]

MAX_SANDWICH_MODELS = 999  #: the most parameter draws
CLIP_SD = 3.0  #: each drawn coordinate within this many standard errors of the fit
#: the standard error beyond which a coordinate of u is held at the fit (log variance, log
#: lengths, angle in radians, log noise): :data:`~roughgp.inference.whittle_fit.UNDETERMINED_SE`
UNDETERMINED_SD = UNDETERMINED_SE
#: the standard error of the log variance or a log length beyond which the draws are refused:
#: a factor of 2 per standard error (module docstring)
POWERLESS_SD = math.log(2.0)
_EQUATIONS = ("eq18", "eq18-matern")
_NAMES = ("variance_um2", "lambda_a_um", "lambda_b_um", "angle_deg", "noise_variance_um2")


class SandwichDraws(NamedTuple):
    """What :func:`sandwich_models` returns: the drawn ``models`` and the hyperparameters
    ``held`` at the fit (the map does not determine them)."""

    models: tuple
    held: tuple


def sandwich_models(model: FittedModel, fit: WhittleFit | None, valid, n_models, *, seed=0,
                    n_score_draws=40) -> SandwichDraws:
    """``n_models`` eq 18 models whose parameters are drawn from :math:`N(\\hat u, \\Sigma)`
    (module docstring), centred on ``model``'s own hyperparameters (after any range
    adjustment of the fit), for ``check_model(..., models=...)``.

    Args:
        model: a surface model of equation ``"eq18"`` or ``"eq18-matern"`` fitted by
            ``fit_surface_model(..., likelihood="whittle")``.
        fit: that fit's :class:`~roughgp.inference.whittle_fit.WhittleFit` (``block_fit``:
            :math:`H` its observed information), or None where only the model is at hand (a
            model file): :math:`H` the expected information of ``model`` on ``valid``
            (:func:`~roughgp.inference.whittle_fit.implied_fit`).
        valid: the boolean map of the points the fit used (the filtered heights' finite
            points), of the fitted shape; with ``fit=None``, the fitted grid (all True where
            the holes are not known).
        n_models: an integer in [1, :data:`MAX_SANDWICH_MODELS`].
        seed: an integer >= 0 (the score draws of :math:`J` and the parameter draws).
        n_score_draws: surfaces for :math:`J` (an integer >= 10).

    Raises:
        ValueError: a model of another equation, a fit that is not a Whittle fit, a model
            whose lengths the fit replaced because the map does not pin them
            (:func:`~roughgp.surface_models.in_range.keep_in_range`: the model's ``fit`` holds
            ``"range"``; its centre is no optimum, and the spread of draws around it was
            such that the check could not say no), a variance or length determined only within
            a factor of more than 2 per standard error (:data:`POWERLESS_SD`), a sandwich
            covariance that is not finite (a length far beyond the map, or a model the grid
            cannot draw), or a grid that determines none of the parameters: the predictive
            simulations cannot be drawn this way, and the message says so.
    """
    if not isinstance(model, FittedModel) or model.equation not in _EQUATIONS:
        raise ValueError(f"model must be an eq 18 surface model ({', '.join(_EQUATIONS)}), got "
                         f"{getattr(model, 'equation', type(model).__name__)!r}")
    if fit is not None and not isinstance(fit, WhittleFit):
        raise ValueError("fit must be the WhittleFit of fit_surface_model(..., "
                         f"likelihood='whittle') or None, got {type(fit).__name__}")
    capped = model.fit.get("range")
    if capped:
        raise ValueError("the fit's lengths were replaced (" + "; ".join(map(str, capped))
                         + "): the map does not pin them, and a normal approximation "
                         "around a replaced optimum says nothing of their uncertainty; draw "
                         "the predictive simulations by refits or fit a larger part of the "
                         "surface")
    n = check_integer("n_models", n_models, 1, MAX_SANDWICH_MODELS)
    if not isinstance(seed, (int, np.integer)) or seed < 0:
        raise ValueError(f"seed must be an integer >= 0, got {seed!r}")
    valid = np.asarray(valid, dtype=bool)
    rng = as_generator(seed)
    if fit is not None and not np.all(np.isfinite(fit.covariance)):
        fit = None  # the observed information is singular: the expected one, held where needed
    if fit is None:
        hp = model.hyperparameters
        groove = GrooveParameters(hp["variance_um2"], (hp["lambda_a_um"], hp["lambda_b_um"]),
                                  math.radians(hp["angle_deg"]))
        fit = implied_fit(groove, hp["noise_variance_um2"], valid, model.spacing,
                          nu=float(hp.get("nu", 0.5)))
    sigma = robust_covariance(fit, valid, model.spacing, n_draws=n_score_draws, seed=rng)
    if not np.all(np.isfinite(sigma)):
        raise ValueError("the Whittle fit's sandwich covariance is not finite (a parameter the "
                         "map does not determine, or a length far beyond the map): draw the "
                         "predictive simulations by refits (roughgp.checking.predictive)")
    sigma = 0.5 * (sigma + sigma.T)
    sd = np.sqrt(np.clip(np.diag(sigma), 0.0, None))
    free = (sd > 0) & (sd <= np.asarray(UNDETERMINED_SD))
    if not free.any():
        raise ValueError("the fitted grid determines none of eq 18's parameters: no "
                         "predictive simulations can be drawn from its sandwich covariance")
    loose = [(name, float(v)) for name, v in zip(_NAMES[:3], sd[:3])
             if not 0.0 < v <= POWERLESS_SD]   # 0: held by a singular information
    if loose:
        raise ValueError("the fit determines " + ", ".join(
            f"{name} only within a factor of {math.exp(v):.3g}" if v > 0 else
            f"{name} not at all (its information is singular)" for name, v in loose)
            + " per standard error (at most 2 for the predictive draws): the draws within 3 "
            "standard errors would span a factor of 64 or more and the check could not say no; "
            "fit a larger part of the surface, or check the plug-in simulations")
    sigma = np.where(np.outer(free, free), sigma, 0.0)
    sd = np.where(free, sd, 0.0)
    values, vectors = np.linalg.eigh(sigma)
    root = vectors * np.sqrt(np.clip(values, 0.0, None))
    centre = eq18_coordinates(model.hyperparameters)
    longest = max(max(k * d for k, d in zip(valid.shape, model.spacing)),
                  model.hyperparameters["lambda_a_um"])
    held = tuple(name for name, f in zip(_NAMES, free) if not f)
    out = []
    for _ in range(n):
        u = centre + root @ rng.standard_normal(len(centre))
        u = np.clip(u, centre - CLIP_SD * sd, centre + CLIP_SD * sd)
        lam_a, lam_b = (min(math.exp(v), longest) for v in u[1:3])
        angle = u[3]
        if lam_a < lam_b:
            lam_a, lam_b, angle = lam_b, lam_a, angle + math.pi / 2
        angle = (angle + math.pi / 2) % math.pi - math.pi / 2
        hp = {**model.hyperparameters, "variance_um2": math.exp(u[0]), "lambda_a_um": lam_a,
              "lambda_b_um": lam_b, "angle_deg": math.degrees(angle),
              "noise_variance_um2": math.exp(u[4])}
        hp.update({name: model.hyperparameters[name] for name in held})
        out.append(dataclasses.replace(model, hyperparameters=hp))
    return SandwichDraws(tuple(out), held)
