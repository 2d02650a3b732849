r"""Draws of a latent surface on a regular grid, eq 10: :math:`\mathbf G \sim \mathcal N(0, \mathbf R)`.

``sample_grid`` is the single entry point. Methods:

* ``"cholesky"``: exact, dense. :math:`\mathbf R = \mathbf L\mathbf L^\top` and
  :math:`\mathbf g = \mathbf L\boldsymbol\varepsilon` (the reparameterisation of section 2.2).
  Memory grows as :math:`N^2` and time as :math:`N^3`: the call refuses, before allocating,
  when the covariance would not fit in memory.
"""

from __future__ import annotations

import os
import warnings
from typing import Callable

import numpy as np
import scipy.linalg

from roughgp.grid import centred_lags, normalize

__all__ = ["sample_grid", "grid_covariance", "METHODS"]

METHODS = ("auto", "cholesky")

_BYTES = 8  # float64


def _acvf_of(kernel) -> Callable:
    acvf = getattr(kernel, "acvf", None)
    if callable(acvf):
        return acvf
    if callable(kernel):
        return kernel
    raise ValueError(f"kernel must be a roughgp StationaryKernel or a function of lags, "
                     f"got {type(kernel).__name__}")


def _available_bytes() -> int:
    try:
        return os.sysconf("SC_AVPHYS_PAGES") * os.sysconf("SC_PAGE_SIZE")
    except (ValueError, OSError, AttributeError):  # pragma: no cover - non-POSIX
        return 8 * 2**30


def _rng(seed) -> np.random.Generator:
    if isinstance(seed, np.random.Generator):
        return seed
    if seed is None or isinstance(seed, (int, np.integer)):
        return np.random.default_rng(seed)
    raise ValueError(f"seed must be an int, None or a numpy.random.Generator, got {seed!r}")


def grid_covariance(kernel, shape, spacing=1.0):
    """The covariance matrix R of eq 10 for the grid points in row-major order, (N, N).

    Uses stationarity: the ACVF is evaluated once on the (2n - 1)-point lag grid of each axis
    and the matrix is gathered from that table, never from an (N, N, D) lag array.
    """
    shape, spacing = normalize(shape, spacing)
    acvf = _acvf_of(kernel)
    table = np.asarray(acvf(centred_lags(tuple(2 * n - 1 for n in shape), spacing)),
                       dtype=np.float64)
    if not np.all(np.isfinite(table)):
        raise ValueError("kernel returned non-finite covariances on this grid")
    if len(shape) == 1:
        (n,) = shape
        i = np.arange(n)
        return table[i[None, :] - i[:, None] + n - 1]
    ny, nx = shape
    iy, ix = np.arange(ny), np.arange(nx)
    dy = (iy[None, :] - iy[:, None] + ny - 1)[:, None, :, None]
    dx = (ix[None, :] - ix[:, None] + nx - 1)[None, :, None, :]
    return table[dy, dx].reshape(ny * nx, ny * nx)


def _cholesky_factor(covariance):
    """Lower Cholesky factor, with the smallest diagonal jitter (1e-12 .. 1e-6 of the mean
    variance) that makes a numerically semi-definite matrix factorisable, and a warning
    naming the jitter when one was needed."""
    scale = float(np.mean(np.diag(covariance)))
    for rel in (0.0, 1e-12, 1e-10, 1e-8, 1e-6):
        try:
            a = covariance + rel * scale * np.eye(len(covariance)) if rel else covariance
            factor = scipy.linalg.cholesky(a, lower=True, check_finite=False)
        except np.linalg.LinAlgError:
            continue
        if rel:
            warnings.warn(f"covariance needed a diagonal jitter of {rel:g} x the mean variance "
                          f"to factorise", stacklevel=3)
        return factor
    raise ValueError("the covariance is not positive semi-definite (Cholesky failed even with "
                     "a jitter of 1e-6 x the mean variance): the kernel is not a valid ACVF "
                     "on this grid")


def sample_grid(kernel, shape, *, spacing=1.0, n_samples=1, method="auto", seed=None):
    """Draw ``n_samples`` latent surfaces G ~ N(0, R) (eq 10) on a regular grid.

    Args:
        kernel: a :class:`roughgp.kernels.StationaryKernel` (its ``acvf`` is used) or a
            function of lags of shape (..., D) returning the ACVF.
        shape: ``(n,)`` for a profile or ``(ny, nx)`` for a surface (array order).
        spacing: grid spacing, scalar or per axis in array order.
        n_samples: number of independent draws (>= 1).
        method: ``"cholesky"`` (exact, dense) or ``"auto"``.
        seed: int, None or ``numpy.random.Generator``; the same seed gives the same array.

    Returns:
        float64 array of shape ``(n_samples, *shape)``.
    """
    shape, spacing = normalize(shape, spacing)
    if not isinstance(n_samples, (int, np.integer)) or n_samples < 1:
        raise ValueError(f"n_samples must be an integer >= 1, got {n_samples!r}")
    if method not in METHODS:
        raise ValueError(f"method must be one of {METHODS}, got {method!r}")
    rng = _rng(seed)
    n_points = int(np.prod(shape))
    needed = 2 * n_points**2 * _BYTES  # the covariance and its factor
    available = _available_bytes()
    if needed > 0.8 * available:
        raise ValueError(f"method='cholesky' on shape {shape} needs a dense {n_points} x "
                         f"{n_points} covariance: about {needed / 2**30:.1f} GiB, but only "
                         f"{available / 2**30:.1f} GiB are free; use a smaller grid")
    factor = _cholesky_factor(grid_covariance(kernel, shape, spacing))
    noise = rng.standard_normal((n_points, int(n_samples)))
    return (factor @ noise).T.reshape((int(n_samples), *shape))
