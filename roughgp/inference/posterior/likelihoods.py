r"""Ready-made log-likelihoods for :class:`~roughgp.inference.posterior.priors.PosteriorModel`.

:func:`profile_likelihood`: a 1-D profile on a regular grid, exact in :math:`O(n^2)` by
:func:`roughgp.gp.toeplitz.toeplitz_log_likelihood`; :func:`grid_likelihood`: a small 2-D
patch, dense Cholesky (eq 10's covariance plus noise), on the CPU or a device.
"""

from __future__ import annotations

import math
from typing import Callable

import numpy as np
import scipy.linalg

from roughgp.common.checks import check_finite, check_positive
from roughgp.common.device import check_memory, gaussian_log_density
from roughgp.common.device import resolve as resolve_device
from roughgp.common.grid import normalize
from roughgp.common.threads import blas_threads_for
from roughgp.gp.toeplitz import toeplitz_log_likelihood
from roughgp.sampling.grid_sampler import grid_covariance

MAX_GRID_POINTS = 4096
"""Largest patch :func:`grid_likelihood` accepts: one evaluation factorises an (N, N) matrix
(4096 points: 128 MiB and about a second; a chain needs 10^4-10^5 evaluations)."""

_LOG_2PI = math.log(2.0 * math.pi)


def profile_likelihood(z, spacing, acvf_fn: Callable) -> Callable:
    """Log-likelihood of a profile on a regular grid: a function of a dict of parameters.

    Args:
        z: shape (n,), zero mean (used as given: remove the mean first).
        spacing: the grid spacing (> 0).
        acvf_fn: ``acvf_fn(params, lags) -> values``: the noise-free ACVF (eq 10) at
            ``lags = spacing * arange(n)``.

    Returns:
        ``loglik(params)``; ``params["noise_variance"]``, where present, is added at lag 0
        (the white noise of eq 8). Exact, :math:`O(n^2)` per call
        (:func:`roughgp.gp.toeplitz.toeplitz_log_likelihood`); a ``ValueError`` where the
        covariance is not positive definite.
    """
    z = np.asarray(z, dtype=np.float64)
    if z.ndim != 1 or z.size < 2:
        raise ValueError(f"z must be a profile of shape (n,) with n >= 2, got shape {z.shape}")
    check_finite("z", z)
    check_positive("spacing", spacing)
    lags = float(spacing) * np.arange(z.size, dtype=np.float64)

    def loglik(params):
        r = np.array(acvf_fn(params, lags), dtype=np.float64).reshape(-1)
        if r.shape != (z.size,):
            raise ValueError(f"acvf_fn must return {z.size} values, got shape {r.shape}")
        r[0] += params.get("noise_variance", 0.0)
        return toeplitz_log_likelihood(z, r)

    return loglik


def check_patch(z, device=None):
    z = np.asarray(z, dtype=np.float64)
    if z.ndim != 2:
        raise ValueError(f"z must be a patch of shape (ny, nx), got shape {z.shape}")
    if device is None and z.size > MAX_GRID_POINTS:
        raise ValueError(f"z has {z.size} points ({z.shape[0]} x {z.shape[1]}); the dense "
                         f"likelihood allows at most MAX_GRID_POINTS = {MAX_GRID_POINTS} "
                         f"on the CPU (use a smaller patch, a profile with "
                         f"profile_likelihood, or device='cuda' on a GPU)")
    if device is not None:
        # the covariance, its factor and the gather's index, each N x N of 8 bytes
        check_memory(3 * 8 * z.size**2, device,
                     f"the dense likelihood of a {z.shape[0]} x {z.shape[1]} patch")
    check_finite("z", z)
    return z


def grid_likelihood(z, spacing, kernel_factory: Callable, *, device=None) -> Callable:
    """Log-likelihood of a 2-D patch (dense Cholesky, eq 12): a function of a dict.

    Args:
        z: shape (ny, nx), zero mean (used as given); on the CPU at most
            :data:`MAX_GRID_POINTS` points.
        spacing: scalar or ``(dy, dx)``, as in :func:`roughgp.sampling.grid_covariance`.
        kernel_factory: ``kernel_factory(params)`` -> a roughgp kernel or a function of lags
            of shape (..., 2) (the ACVF of eq 10, without noise).
        device: None (numpy and scipy) or a torch device such as ``"cuda"``
            (:mod:`roughgp.common.device`): the covariance is gathered and factorised there, and the
            patch is limited by the device's memory instead of :data:`MAX_GRID_POINTS`.

    Returns:
        ``loglik(params)``: the Gaussian log density of ``z`` with covariance
        ``grid_covariance(kernel, shape, spacing) + params["noise_variance"] * I`` (noise 0
        where absent); a ``ValueError`` where that matrix is not positive definite.
    """
    device = resolve_device(device)
    z = check_patch(z, device)
    shape, spacing = normalize(z.shape, spacing)
    y = z.reshape(-1)
    const = 0.5 * y.size * _LOG_2PI
    not_pd = "the covariance of these hyperparameters is not positive definite on this patch"

    if device is not None:
        import torch

        y_dev = torch.as_tensor(y, device=device)

        def loglik_on_device(params):
            cov = grid_covariance(kernel_factory(params), shape, spacing, device=device)
            cov.diagonal().add_(params.get("noise_variance", 0.0))
            try:
                return float(gaussian_log_density(cov, y_dev))
            except np.linalg.LinAlgError:
                raise ValueError(not_pd) from None

        return loglik_on_device

    def loglik(params):
        cov = grid_covariance(kernel_factory(params), shape, spacing)
        cov[np.diag_indices_from(cov)] += params.get("noise_variance", 0.0)
        try:
            with blas_threads_for(y.size):
                factor = scipy.linalg.cho_factor(cov, lower=True, check_finite=True)
        except np.linalg.LinAlgError:
            raise ValueError(not_pd) from None
        alpha = scipy.linalg.cho_solve(factor, y, check_finite=False)
        return float(-0.5 * y @ alpha - np.sum(np.log(np.diag(factor[0]))) - const)

    return loglik
