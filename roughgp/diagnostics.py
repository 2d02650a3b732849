r"""Checks of sampled surfaces against their model: the covariance error of section 3.1.

The paper judges a sampler by the mean absolute error, element-wise, between the given
covariance matrix :math:`\mathbf R` (eq 10) and the unbiased sample covariance
:math:`\mathbf S` of ``n`` draws. Even an exact sampler has an error: for Gaussian draws,
:math:`(n-1)\mathbf S` is Wishart, so :math:`\operatorname{Var}(S_{ij}) = (R_{ij}^2 + R_{ii}R_{jj})/(n-1)`,
and with :math:`S_{ij}` close to normal (a sum of ``n - 1`` products),
:math:`\mathbb E|S_{ij} - R_{ij}| \approx \sqrt{2/\pi}\,\sqrt{\operatorname{Var}(S_{ij})}`.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["sample_covariance", "covariance_error", "expected_covariance_error"]


def _flatten(samples):
    samples = np.asarray(samples, dtype=np.float64)
    if samples.ndim < 2 or samples.shape[0] < 2:
        raise ValueError(f"samples must have shape (n_samples >= 2, ...), got {samples.shape}")
    return samples.reshape(samples.shape[0], -1)


def sample_covariance(samples):
    """Unbiased sample covariance (sample mean removed, divided by n - 1), shape (N, N)."""
    x = _flatten(samples)
    x = x - x.mean(axis=0)
    return (x.T @ x) / (x.shape[0] - 1)


def covariance_error(samples, covariance):
    """Mean absolute element-wise error between ``covariance`` and the unbiased sample
    covariance of ``samples`` (shape (n_samples, *grid)), as in section 3.1."""
    covariance = np.asarray(covariance, dtype=np.float64)
    s = sample_covariance(samples)
    if s.shape != covariance.shape:
        raise ValueError(f"covariance must have shape {s.shape} for these samples, got "
                         f"{covariance.shape}")
    s -= covariance
    np.abs(s, out=s)
    return float(s.mean())


def expected_covariance_error(covariance, n_samples):
    """E[covariance_error] for an exact Gaussian sampler with ``n_samples`` draws
    (normal approximation of each entry, see the module docstring)."""
    covariance = np.asarray(covariance, dtype=np.float64)
    if not isinstance(n_samples, (int, np.integer)) or n_samples < 2:
        raise ValueError(f"n_samples must be an integer >= 2, got {n_samples!r}")
    d = np.diag(covariance)
    total = 0.0
    for i in range(0, len(d), 512):  # blocks of rows keep memory at 512 x N
        block = covariance[i:i + 512]
        total += np.sqrt(block * block + np.outer(d[i:i + 512], d)).sum()
    return math.sqrt(2 / math.pi) * total / covariance.size / math.sqrt(n_samples - 1)
