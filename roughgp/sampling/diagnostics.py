r"""Checks of sampled surfaces against their model: the covariance error of section 3.1, and
the sampling spread of statistics of one surface.

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

__all__ = ["sample_covariance", "covariance_error", "expected_covariance_error",
           "grid_mean_variance", "sample_variance_sd"]


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
    covariance of ``samples`` (shape ``(n_samples, *grid)``), as in section 3.1."""
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


def _lag_weighted_sum(kernel, shape, spacing, power, noise_variance):
    r""":math:`\sum_{\boldsymbol k} c(\boldsymbol k)\, r(\boldsymbol k \Delta)^p / N^2`, where
    :math:`c(\boldsymbol k) = \prod_d (n_d - |k_d|)` counts the point pairs at lag index
    :math:`\boldsymbol k`: the double sum over all pairs of grid points, in O(N) memory."""
    from roughgp.common.grid import centred_lags, normalize

    shape, spacing = normalize(shape, spacing)
    acvf = getattr(kernel, "acvf", kernel)
    total = 0.0
    counts_x = shape[-1] - np.abs(np.arange(-(shape[-1] - 1), shape[-1]))
    if len(shape) == 1:
        lags = centred_lags((2 * shape[0] - 1,), spacing)
        r = np.asarray(acvf(lags), dtype=np.float64)
        r[shape[0] - 1] += noise_variance
        total = float(np.sum(counts_x * r**power))
    else:
        ny = shape[0]
        row_lags = centred_lags((1, 2 * shape[1] - 1), spacing)[0]  # (2 nx - 1, 2), y = 0
        for ky in range(-(ny - 1), ny):  # one row of lags at a time: O(nx) memory
            lags = row_lags.copy()
            lags[:, 1] = ky * spacing[0]
            r = np.asarray(acvf(lags), dtype=np.float64)
            if ky == 0:
                r[shape[1] - 1] += noise_variance
            total += (ny - abs(ky)) * float(np.sum(counts_x * r**power))
    return total / float(np.prod(shape)) ** 2


def grid_mean_variance(kernel, shape, spacing=1.0, noise_variance=0.0):
    r"""Variance of the mean height :math:`\bar z` of one surface on a grid,
    :math:`\operatorname{Var}(\bar z) = \frac1{N^2}\sum_{i,j} R_{ij}` (R of eq 10, plus the
    noise variance on the diagonal).

    For long correlation lengths (figure 2: :math:`\lambda_a = 500` on 2000 points) it is a
    large part of :math:`r(0)`: removing the sample mean then lowers the empirical ACVF by
    about this much at every lag, and Sq falls short of :math:`\sqrt{r(0)}` on average.
    """
    return _lag_weighted_sum(kernel, shape, spacing, 1, noise_variance)


def sample_variance_sd(kernel, shape, spacing=1.0, noise_variance=0.0):
    r"""Standard deviation of the height variance of one surface about a known zero mean,
    :math:`\operatorname{sd}(\frac1N\sum z^2) = \sqrt{2\sum_{i,j} R_{ij}^2}/N` (Gaussian
    heights: :math:`\operatorname{Cov}(z_i^2, z_j^2) = 2R_{ij}^2`). By the delta method
    Sq then spreads by about ``sample_variance_sd / (2 Sq)``."""
    return math.sqrt(2 * _lag_weighted_sum(kernel, shape, spacing, 2, noise_variance))
