r"""Eq 18's exponential ACVF in one dimension plus white noise (eq 8), fitted to a complete
profile by the Whittle likelihood of its periodogram (beyond the paper; the roughness on top of
the feed marks of the ``periodic-mark-profile`` rung, issue 41).

On a grid of spacing :math:`\Delta` the exponential ACVF :math:`\sigma_k^2 e^{-|\tau|/\lambda}`
is an AR(1) process of coefficient :math:`a = e^{-\Delta/\lambda}`, whose spectral density per
unit of the angular frequency :math:`\omega` (normalised so that its mean over
:math:`[0, \pi]` is the variance) is :math:`\sigma_k^2 (1 - a^2) / (1 - 2a\cos\omega + a^2)`;
white noise adds :math:`\sigma^2`. The Whittle likelihood :math:`-\sum_k [\log S(\omega_k) +
I_k / S(\omega_k)]` over the Fourier frequencies :math:`0 < \omega_k < \pi` (the periodogram
:math:`I_k = |\sum_j z_j e^{-i \omega_k j}|^2 / n` of the centred profile) is maximised over the
logs of :math:`\sigma_k^2, \lambda, \sigma^2` by L-BFGS-B from the moments' start.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
from scipy import optimize

__all__ = ["ExponentialProfileFit", "fit_exponential_profile", "exponential_spectrum"]


@dataclasses.dataclass(frozen=True)
class ExponentialProfileFit:
    """The fit: ``variance`` (um^2), ``lengthscale`` (um), ``noise_variance`` (um^2) and the
    Whittle log likelihood at the optimum."""

    variance: float
    lengthscale: float
    noise_variance: float
    log_likelihood: float


def exponential_spectrum(omega, variance, lengthscale, noise_variance, spacing):
    """:math:`S(\\omega)` of the module docstring at angular frequencies ``omega`` (radians per
    sample)."""
    a = math.exp(-spacing / lengthscale)
    return variance * (1 - a * a) / (1 - 2 * a * np.cos(omega) + a * a) + noise_variance


def fit_exponential_profile(z, spacing=1.0) -> ExponentialProfileFit:
    """Fit the exponential ACVF plus noise to the complete profile ``z`` (um) at ``spacing``
    um (module docstring); lengths bounded to [spacing / 20, 20 * the profile's length]."""
    z = np.asarray(z, dtype=np.float64)
    if z.ndim != 1 or z.size < 16:
        raise ValueError(f"z must be a profile of at least 16 points, got shape {z.shape}")
    if not np.isfinite(z).all():
        raise ValueError("z must be complete (no NaN): the Whittle fit of a profile needs "
                         "every point")
    n = z.size
    centred = z - z.mean()
    total = float(centred.var())
    if not total > 0:
        raise ValueError("z must not be constant")
    periodogram = np.abs(np.fft.rfft(centred)) ** 2 / n
    k = np.arange(1, (n - 1) // 2 + 1)
    omega = 2 * math.pi * k / n
    power = periodogram[k]
    bounds = [(math.log(total) - 12, math.log(total) + 6),
              (math.log(spacing / 20), math.log(20 * n * spacing)),
              (math.log(total) - 18, math.log(total) + 3)]

    def negative(u):
        s = exponential_spectrum(omega, math.exp(u[0]), math.exp(u[1]), math.exp(u[2]),
                                 spacing)
        return float(np.sum(np.log(s) + power / s))

    lag_one = float(np.mean(centred[1:] * centred[:-1]) / total)
    length = -spacing / math.log(min(max(lag_one, 0.05), 0.999))
    starts = [np.array([math.log(0.9 * total), math.log(length), math.log(0.1 * total)]),
              np.array([math.log(0.5 * total), math.log(3 * spacing), math.log(0.5 * total)])]
    best = min((optimize.minimize(negative, u0, method="L-BFGS-B", bounds=bounds)
                for u0 in starts), key=lambda r: r.fun)
    variance, lengthscale, noise = (math.exp(v) for v in best.x)
    return ExponentialProfileFit(variance, lengthscale, noise, -float(best.fun))
