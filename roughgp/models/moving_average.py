r"""A GP as a continuous moving average of white noise (eq 15-17).

A stationary GP can be written as white noise smoothed by a feature map :math:`\beta`,

.. math::  G(x) = \int \beta(\kappa)\, dB(x - \kappa) \quad (16), \qquad
           k(\tau) = \int \beta(\kappa)\, \beta(\kappa + \tau)\, d\kappa \quad (17)

(real :math:`\beta`, D = 1). On a grid of step ``h`` the integral becomes a discrete
convolution with independent increments :math:`\Delta B \sim \mathcal N(0, h)`,
:math:`G_n = \sum_m \beta(m h)\, \Delta B_{n-m}` (a linear process, eq 13), whose ACVF is the
Riemann sum :math:`h \sum_m \beta(m h) \beta(m h + \tau)` of eq 17: the quadrature converges to
the kernel as ``h -> 0``.

Two feature maps with closed-form kernels:

* Gaussian, :math:`\beta(\kappa) = c\, e^{-\kappa^2 / (2 s^2)}` gives the squared-exponential
  kernel :math:`c^2 \sqrt\pi\, s\, e^{-\tau^2 / (4 s^2)}`: lengthscale :math:`\ell = \sqrt2\, s`.
* one-sided exponential, :math:`\beta(\kappa) = c\, e^{-\kappa/\lambda}` for :math:`\kappa \ge 0`
  (a causal filter) gives the exponential kernel :math:`c^2 \frac{\lambda}{2} e^{-|\tau|/\lambda}`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy import signal

from roughgp.common.checks import as_generator as _rng
from roughgp.common.checks import check_positive

__all__ = ["FeatureMap", "gaussian_feature_map", "exponential_feature_map",
           "feature_map_acvf", "moving_average_sample"]


@dataclass(frozen=True)
class FeatureMap:
    """A feature map :math:`\\beta` of eq 16 with the kernel it produces (eq 17).

    Attributes:
        beta: the map, a vectorised function of :math:`\\kappa`.
        support: ``(lo, hi)``: :math:`\\beta` is negligible (< 1e-16 of its peak) outside.
        kernel: the closed-form ACVF of eq 17, a function of the lag.
        name: what it is, for plots.
    """

    beta: callable
    support: tuple
    kernel: callable
    name: str


def gaussian_feature_map(variance, lengthscale) -> FeatureMap:
    """The Gaussian feature map whose eq-17 kernel is the squared exponential
    ``variance * exp(-tau^2 / (2 lengthscale^2))``."""
    check_positive("variance", variance)
    check_positive("lengthscale", lengthscale)
    s = lengthscale / math.sqrt(2)
    c = math.sqrt(variance / (math.sqrt(math.pi) * s))
    reach = s * math.sqrt(2 * math.log(1e16))
    return FeatureMap(lambda k: c * np.exp(-np.asarray(k) ** 2 / (2 * s * s)), (-reach, reach),
                      lambda t: variance * np.exp(-np.asarray(t) ** 2 / (2 * lengthscale ** 2)),
                      "Gaussian feature map -> squared exponential")


def exponential_feature_map(variance, lengthscale) -> FeatureMap:
    """The one-sided (causal) exponential feature map whose eq-17 kernel is the exponential
    ``variance * exp(-|tau| / lengthscale)`` (the Ornstein-Uhlenbeck process)."""
    check_positive("variance", variance)
    check_positive("lengthscale", lengthscale)
    c = math.sqrt(2 * variance / lengthscale)
    return FeatureMap(lambda k: np.where(np.asarray(k) >= 0,
                                         c * np.exp(-np.clip(k, 0, None) / lengthscale), 0.0),
                      (0.0, lengthscale * math.log(1e16)),
                      lambda t: variance * np.exp(-np.abs(np.asarray(t)) / lengthscale),
                      "one-sided exponential feature map -> exponential")


def _weights(feature_map: FeatureMap, step):
    """beta at the grid points of its support, kappa_m = m * step."""
    lo, hi = feature_map.support
    m = np.arange(math.floor(lo / step), math.ceil(hi / step) + 1)
    return feature_map.beta(m * step)


def feature_map_acvf(feature_map: FeatureMap, n_lags, step):
    """Eq 17 by the Riemann sum on a grid of ``step``: ``h sum_m beta(m h) beta(m h + k h)``
    for lags ``k = 0 .. n_lags - 1``. This is also the exact ACVF of the discretised moving
    average of :func:`moving_average_sample` with the same step."""
    check_positive("step", step)
    if not isinstance(n_lags, (int, np.integer)) or n_lags < 1:
        raise ValueError(f"n_lags must be an integer >= 1, got {n_lags!r}")
    w = _weights(feature_map, step)
    full = np.correlate(w, w, mode="full")[w.size - 1:] * step
    out = np.zeros(n_lags)
    out[:min(n_lags, full.size)] = full[:n_lags]
    return out


def moving_average_sample(feature_map: FeatureMap, n, step, *, n_samples=1, seed=None):
    """Draws of eq 16 on ``n`` points of spacing ``step``: white-noise increments
    :math:`\\Delta B \\sim \\mathcal N(0, h)` convolved with :math:`\\beta` on the grid
    (``scipy.signal.fftconvolve``). Returns shape ``(n_samples, n)``."""
    check_positive("step", step)
    for name, value in (("n", n), ("n_samples", n_samples)):
        if not isinstance(value, (int, np.integer)) or value < 1:
            raise ValueError(f"{name} must be an integer >= 1, got {value!r}")
    w = _weights(feature_map, step)
    rng = _rng(seed)
    increments = math.sqrt(step) * rng.standard_normal((n_samples, n + w.size - 1))
    return signal.fftconvolve(increments, w[None, :], mode="valid", axes=1)
