r"""Noise models, eq 8: :math:`Z(\mathbf x_n) \mid g(\mathbf x_n) \sim p(z(\mathbf x_n) \mid g(\mathbf x_n))`.

The surface is the latent GP draw passed through a noise model (eq 9). The paper uses Gaussian
noise of variance :math:`\sigma^2 = 1` everywhere. A noise model implements ``sample``
(a surface from a latent draw) and ``variance`` (the variance it adds), so that a non-Gaussian
height model can implement the same interface later.
"""

from __future__ import annotations

from abc import ABC, abstractmethod

import numpy as np

from roughgp.common.checks import as_generator as _rng
from roughgp.common.checks import check_finite, check_nonnegative

__all__ = ["NoiseModel", "GaussianNoise"]


class NoiseModel(ABC):
    """Interface of eq 8: maps a latent surface ``g`` to a surface ``z``."""

    @abstractmethod
    def sample(self, latent, seed=None) -> np.ndarray:
        """A surface ``z`` drawn from ``p(z | g)`` for every point of ``latent`` (any shape)."""

    @property
    @abstractmethod
    def variance(self) -> float:
        """The variance the noise adds to each height."""


class GaussianNoise(NoiseModel):
    r"""Gaussian noise, :math:`p(z \mid g) = \mathcal N(z; g, \sigma^2)` (eq 8, 11).

    Args:
        variance: :math:`\sigma^2 \ge 0` (the paper: 1).
    """

    def __init__(self, variance: float = 1.0):
        check_nonnegative("variance", variance)
        self._variance = float(variance)

    @property
    def variance(self) -> float:
        return self._variance

    def sample(self, latent, seed=None):
        latent = np.asarray(latent)
        check_finite("latent", latent)
        rng = _rng(seed)
        return latent + np.sqrt(self._variance) * rng.standard_normal(latent.shape)

    def __repr__(self):
        return f"GaussianNoise(variance={self._variance})"
