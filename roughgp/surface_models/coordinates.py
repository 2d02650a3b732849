r"""An eq 18 model's hyperparameters as the coordinates its fits and draws work in:
:math:`u = (\log\sigma_f^2, \log\lambda_a, \log\lambda_b, \phi, \log\sigma^2)`, the order of
:data:`~roughgp.inference.tile_fit.PARAMETERS` (the variance, the correlation lengths and the
lay angle of eq 18, the noise variance of eq 8; the angle in radians).

One home for the centre that the predictive draws
(:mod:`roughgp.checking.sandwich_draws`) and the population's regions
(:mod:`roughgp.surface_models.population_draw`) both draw around.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["eq18_coordinates"]


def eq18_coordinates(hyperparameters) -> np.ndarray:
    """``u`` (module docstring) of an eq 18 model file's ``hyperparameters``: a mapping with
    ``variance_um2``, ``lambda_a_um``, ``lambda_b_um``, ``angle_deg`` and
    ``noise_variance_um2``, each finite and, but the angle, > 0."""
    hp = hyperparameters
    names = ("variance_um2", "lambda_a_um", "lambda_b_um", "noise_variance_um2")
    for name in names:
        value = hp.get(name) if hasattr(hp, "get") else None
        if not isinstance(value, (int, float, np.floating, np.integer)) or not (
                math.isfinite(value) and value > 0):
            raise ValueError(f"hyperparameters[{name!r}] must be a finite number > 0, "
                             f"got {value!r}")
    angle = hp.get("angle_deg")
    if not isinstance(angle, (int, float, np.floating, np.integer)) or not math.isfinite(angle):
        raise ValueError(f"hyperparameters['angle_deg'] must be a finite number, got {angle!r}")
    return np.array([math.log(hp["variance_um2"]), math.log(hp["lambda_a_um"]),
                     math.log(hp["lambda_b_um"]), math.radians(angle),
                     math.log(hp["noise_variance_um2"])])
