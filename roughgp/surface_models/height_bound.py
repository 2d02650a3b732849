"""What a model may imply: heights within the readers' plausibility limit (beyond the paper).

The schema (:mod:`roughgp.surface_models.schema`) bounds each field of a model file on its own;
together they can still imply surfaces no instrument measures: a ``psd_um4`` table of 1e30, a
variance and a noise of 1e12 um^2, eq 21 weights of 1e12 or IAAFT quantiles of +-1e9 um drew
heights of 1e6 to 1e14 um. :func:`check_height_bound` refuses a model whose draws would reach
beyond :data:`roughgp.io.plausibility.BOUNDS` ``["height"]`` (1 m, what the readers accept of a
measurement) at the normal score :data:`EXTREME_SCORE` (the most extreme point of the largest
draw, 2**24 points, lies at a score of about 5.4): the mean plus that many standard deviations
(latent plus noise) for Gaussian heights, the Johnson marginal's value there, the IAAFT
marginal's quantile function extended there. It is checked when a model file is read and
before every draw.
"""

from __future__ import annotations

import math

import numpy as np

from roughgp.io.plausibility import BOUNDS
from roughgp.surface_models.schema import ModelFileError

__all__ = ["EXTREME_SCORE", "HEIGHT_LIMIT_UM", "extreme_height", "check_height_bound"]

#: the normal score at which a model's heights are bounded (a probability of 1e-9 per point)
EXTREME_SCORE = 6.0
#: the largest absolute height a model may imply, um: the readers' (1 m)
HEIGHT_LIMIT_UM = BOUNDS["height"]
#: the field of each equation that sets its heights' scale
_SCALE_FIELD = {"eq18": "variance_um2", "eq18-matern": "variance_um2", "sm2d": "weights_um2",
                "eq21": "weights_um2", "measured-psd": "psd_um4 and its core's ratios",
                "eq18-field": "variance_um2",
                "eq18-population": "variance_um2, log_variance_sd",
                "periodic-mark": "mark_um, depth_sd_um, lay_sd_um, variance_um2",
                "periodic-mark-profile": "mark_um, depth_sd_um, variance_um2"}


def extreme_height(model) -> tuple[float, str]:
    """``(height, why)``: the largest absolute height (um) ``model``'s draws reach at the normal
    score :data:`EXTREME_SCORE`, and the fields it comes from, in words."""
    mean = abs(float(model.hyperparameters.get("mean_um", 0.0)))
    if model.equation == "eq18-field":  # the roughest anchor, not the mean over them
        latent = max(max(row) for row in model.hyperparameters["variance_um2"])
    elif model.equation == "eq18-population":  # a region EXTREME_SCORE spreads rougher
        hp = model.hyperparameters
        latent = hp["variance_um2"] * math.exp(EXTREME_SCORE * hp["log_variance_sd"])
    elif model.equation in ("periodic-mark", "periodic-mark-profile"):
        hp = model.hyperparameters         # the mark's highest point, then the random parts
        mean += float(np.max(np.abs(hp["mark_um"])))
        latent = hp["depth_sd_um"] ** 2 + hp.get("lay_sd_um", 0.0) ** 2 + hp["variance_um2"]
    else:
        latent = model.latent_variance()
    variance = latent + model.noise_variance
    scale = _SCALE_FIELD[model.equation]
    why = (f"|mean_um| {mean:.3g} um + {EXTREME_SCORE:g} sd of a variance of {variance:.3g} "
           f"um^2 ({scale} and noise_variance_um2)")
    if model.marginal_method == "iaaft":
        from roughgp.surface_models.iaaft import marginal_values
        ends = marginal_values(model.marginal, [-EXTREME_SCORE, EXTREME_SCORE])
        return float(max(abs(ends[0]), abs(ends[1]))), "the marginal's quantiles_um"
    if model.marginal_method == "johnson" and variance > 0:
        from roughgp.non_gaussian.johnson import johnson_for
        try:
            johnson = johnson_for(model.marginal["skewness"], model.marginal["kurtosis"],
                                  variance)
        except ValueError:  # a pair the draw refuses itself, with its own message
            return mean + EXTREME_SCORE * math.sqrt(variance), why
        ends = johnson.transform([-EXTREME_SCORE, EXTREME_SCORE])
        return mean + float(max(abs(ends[0]), abs(ends[1]))), \
            why + " under the marginal's skewness and kurtosis"
    return mean + EXTREME_SCORE * math.sqrt(variance), why


def check_height_bound(model, source="the model") -> None:
    """Raise :class:`~roughgp.surface_models.schema_numbers.ModelFileError` when ``model`` implies
    heights beyond :data:`HEIGHT_LIMIT_UM` (module docstring), naming the fields and the limit."""
    height, why = extreme_height(model)
    if not height <= HEIGHT_LIMIT_UM:
        sd = HEIGHT_LIMIT_UM / EXTREME_SCORE
        raise ModelFileError(
            f"{source}: the model implies heights up to {height:.3g} um ({why}), beyond the "
            f"{HEIGHT_LIMIT_UM:g} um (1 m) no measured surface reaches: a model's heights "
            f"must stay within +-{HEIGHT_LIMIT_UM:g} um at {EXTREME_SCORE:g} sd (an sd of at "
            f"most {sd:.3g} um, a variance of at most {sd * sd:.3g} um^2)")
