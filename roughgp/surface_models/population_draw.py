r"""The ``eq18-population`` model's draws: each surface its own region
(:mod:`roughgp.surface_models.population_model`, whose docstring gives the model), kept apart
from the fit so that :class:`~roughgp.surface_models.model.FittedModel` can draw it without
importing the fit's chain.

A region's parameters are :math:`u = \hat\mu + s\,t_{k-2}` per parameter (log variance, log
lengths, the lay angle; Student's :math:`t` with :math:`k - 2` degrees of freedom for
:math:`k` regions, at least 1, cut at
:data:`~roughgp.surface_models.height_bound.EXTREME_SCORE`), the lengths held within the
schema's range of the spacing and within :data:`~roughgp.inference.whittle_fit.FAR_BEYOND`
times the drawn grid's longer side. Why the last: with few regions the :math:`t` has 1 or 2
degrees of freedom, and a score of 6 on a log length's spread of 0.7 makes a length 70 times
the pooled one; the fit never takes a region's length that far beyond its grid (it cannot
identify it, :mod:`~roughgp.surface_models.in_range`), and drawing one means embedding a torus
of that size: minutes, or no embedding at all. Within the cap such a draw is what the grid can
show of it, a field close to a plane (the F-operator's and the L-filter's share); its surface is eq 18 (circulant embedding,
:func:`roughgp.sampling.sample_grid`) plus the model's noise (eq 8).
"""

from __future__ import annotations

import math

import numpy as np

from roughgp.gp.noise import GaussianNoise
from roughgp.surface_models.coordinates import eq18_coordinates
from roughgp.surface_models.height_bound import EXTREME_SCORE

__all__ = ["SPREAD_NAMES", "region_parameters", "draw_population_model"]

#: the model file's spread of the first four of :data:`~roughgp.inference.tile_fit.PARAMETERS`
#: (the noise is one value, the regions' median: a region's noise is often at its bound)
SPREAD_NAMES = ("log_variance_sd", "log_lambda_a_sd", "log_lambda_b_sd", "angle_sd_deg")


def region_parameters(hyperparameters, spacing, rng, count, longest=None) -> list[dict]:
    """``count`` regions drawn from the population of ``hyperparameters`` (an eq18-population
    model's): each eq 18's ``variance_um2``, ``lambda_a_um``, ``lambda_b_um``, ``angle_deg``
    and ``noise_variance_um2`` (module docstring); ``longest``: None or the largest length
    drawn (um)."""
    hp = hyperparameters
    centre = eq18_coordinates(hp)[:4]
    spread = np.array([hp[name] for name in SPREAD_NAMES], dtype=np.float64)
    spread[3] = math.radians(spread[3])
    low, high = 1e-3 * min(spacing), 1e7 * max(spacing)
    if longest is not None:
        high = max(min(high, float(longest)), low)
    df = max(int(hp["regions"]) - 2, 1)
    scores = np.clip(rng.standard_t(df, size=(count, 4)), -EXTREME_SCORE, EXTREME_SCORE)
    return [{"variance_um2": float(np.exp(u[0])),
             "lambda_a_um": float(np.clip(np.exp(u[1]), low, high)),
             "lambda_b_um": float(np.clip(np.exp(u[2]), low, high)),
             "angle_deg": float((math.degrees(u[3]) + 90.0) % 180.0 - 90.0),
             "noise_variance_um2": float(hp["noise_variance_um2"])}
            for u in centre + spread * scores]


def draw_population_model(model, shape, spacing, rng, count) -> np.ndarray:
    """``count`` surfaces of ``shape`` at ``spacing`` from the eq18-population ``model``, each
    of its own region (:func:`region_parameters`): ``(count, *shape)``."""
    from roughgp.gp.kernels import RotatedExponentialKernel
    from roughgp.inference.whittle_fit import FAR_BEYOND
    from roughgp.sampling import sample_grid
    steps = np.broadcast_to(np.asarray(spacing, dtype=np.float64), (2,))
    longest = FAR_BEYOND * max(n * d for n, d in zip(shape, steps))
    draws = []
    for region in region_parameters(model.hyperparameters, model.spacing, rng, count, longest):
        kernel = RotatedExponentialKernel(region["variance_um2"],
                                          (region["lambda_a_um"], region["lambda_b_um"]),
                                          math.radians(region["angle_deg"]))
        latent = sample_grid(kernel, shape, spacing=spacing, n_samples=1, seed=rng)
        draws.append(GaussianNoise(region["noise_variance_um2"]).sample(latent, seed=rng)[0])
    return np.stack(draws)
