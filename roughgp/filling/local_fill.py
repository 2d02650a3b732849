r"""Unmeasured points filled by moving-window kriging: the GP posterior from nearby points
(beyond the paper).

:func:`roughgp.filling.global_fill.fill_gaps` solves for the posterior with *all* measured
points, by conjugate gradients preconditioned with the kernel's torus. On real measurements
that fails in two ways: a fitted correlation length beyond the field makes the torus a poor
preconditioner (thousands of iterations), and a noise variance near zero makes the system
ill-conditioned. :func:`fill_gaps_locally` bounds the work instead: the grid is cut into
``tile x tile`` cores; for each core with missing points, the measured points of the core and
of a ``margin`` around it give the exact GP posterior (eq 11) of the core's missing points,

.. math::
    \mu_T = \bar y + K_{TO}(K_{OO} + \sigma^2 I)^{-1}(y_O - \bar y), \qquad
    s_T^2 = r(0) - \operatorname{diag}\,K_{TO}(K_{OO} + \sigma^2 I)^{-1}K_{OT},

by one dense Cholesky factor of at most ``(tile + 2 margin)^2`` rows. Leaving out the far
points is the screening approximation of kriging in a moving neighbourhood: for a
kernel that decays within the margin the far points add almost nothing; for a longer one the
posterior is that given the neighbourhood (its sd is then, if anything, too large, never too
small). The sd is exact for that neighbourhood (no Monte Carlo), and no circulant embedding is
needed. Where a core's window holds fewer than ``min_observed`` measured points (inside a
large hole) the margin is doubled until it does, up to the whole grid; a window that then
holds more than ``max_observed`` measured points keeps the ``max_observed`` nearest the core
(kriging in a nearest-neighbour set: the posterior given those points, its sd again never too
small). The work and the memory of one solve are so bounded, whatever the holes: one factor of
at most ``max_observed`` rows.
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np
import scipy.linalg

from roughgp.common.checks import boolean_map, check_integer, check_nonnegative
from roughgp.common.grid import normalize
from roughgp.common.threads import one_blas_thread
from roughgp.filling.global_fill import missing_map
from roughgp.sampling.grid_sampler import acvf_of

__all__ = ["LocalFill", "MAX_OBSERVED", "lag_table", "nearest_to_core", "fill_gaps_locally"]


@dataclass(frozen=True)
class LocalFill:
    """The result of :func:`fill_gaps_locally` (arrays of the grid's shape).

    Attributes:
        mean: posterior mean at the missing points, the input elsewhere.
        sd: posterior sd of the latent surface at the missing points, 0 elsewhere.
        missing: the points filled.
        tiles: cores solved; largest_window: most measured points in one solve.
        seconds: wall time.
    """

    mean: np.ndarray
    sd: np.ndarray
    missing: np.ndarray
    tiles: int
    largest_window: int
    seconds: float

    @property
    def filled(self) -> np.ndarray:
        return self.mean


def lag_table(acvf, shape, spacing):
    """The ACVF on every lag of a grid of ``shape``: ``table[dy + ny - 1, dx + nx - 1]``."""
    ny, nx = shape
    dy, dx = spacing
    jy, jx = np.meshgrid(np.arange(-(ny - 1), ny) * dy, np.arange(-(nx - 1), nx) * dx,
                         indexing="ij")
    table = np.asarray(acvf(np.stack([jx, jy], axis=-1)), dtype=np.float64)
    if table.shape != jy.shape or not np.all(np.isfinite(table)):
        raise ValueError("the kernel must return one finite covariance per lag")
    return table


MAX_OBSERVED = 2048
"""Most measured points in one window's solve: a dense factor of 32 MiB. A full window holds at
most 1600 (this function's default tile and margin) or 784 (those of the fill command); only a
window grown inside a large hole holds more."""


def nearest_to_core(oy, ox, core_rows, core_cols, spacing, count):
    """Indices of the ``count`` points ``(oy, ox)`` nearest the box ``core_rows x core_cols``
    (physical distance, ties broken by the points' order, so the choice is reproducible)."""
    gap_y = np.maximum(np.maximum(core_rows.start - oy, oy - (core_rows.stop - 1)), 0)
    gap_x = np.maximum(np.maximum(core_cols.start - ox, ox - (core_cols.stop - 1)), 0)
    distance = (gap_y * spacing[0]) ** 2 + (gap_x * spacing[1]) ** 2
    return np.sort(np.argsort(distance, kind="stable")[:count])


def fill_gaps_locally(z, kernel, *, noise_variance, spacing=1.0, mask=None, tile=24, margin=8,
                      min_observed=64, predict=None, max_observed=MAX_OBSERVED,
                      progress=None) -> LocalFill:
    """Fill the NaN (and ``mask``-ed) points of ``z`` with the GP posterior mean and sd given
    the measured points within ``margin`` of each ``tile x tile`` core (module docstring).

    Args:
        z: height map ``z[iy, ix]``, NaN where not measured; a constant mean (that of the
            measured points) is removed and added back.
        kernel: a stationary 2-D kernel of :mod:`roughgp.gp.kernels` or a function of lags
            ``(..., 2)`` in (x, y) order.
        noise_variance: :math:`\\sigma^2 \\ge 0` of eq 8.
        spacing: scalar or ``(dy, dx)``.
        mask: optional boolean map: measured points to treat as missing as well.
        tile, margin: core side and margin in points (tile >= 1, margin >= 1).
        min_observed: measured points a window needs before its margin stops growing.
        max_observed: most measured points in one solve (>= min_observed): a window grown
            past it keeps those nearest its core.
        predict: optional boolean map: predict only the missing points it marks (the others
            stay unobserved and NaN in ``mean``); default: all missing points.
        progress: optional callback ``(done, total)``: once with ``done`` 0 before the first
            core, then after each core's solve.
    """
    start = time.perf_counter()
    z, missing = missing_map(z, mask, allow_complete=True)
    check_nonnegative("noise_variance", noise_variance)
    tile = check_integer("tile", tile, 1)
    margin = check_integer("margin", margin, 1)
    min_observed = check_integer("min_observed", min_observed, 1)
    max_observed = check_integer("max_observed", max_observed, min_observed)
    shape, spacing = normalize(z.shape, spacing)
    ny, nx = shape
    table = lag_table(acvf_of(kernel), shape, spacing)
    variance = float(table[ny - 1, nx - 1])
    observed = ~missing
    targets_map = missing
    if predict is not None:
        predict = boolean_map(predict, shape, "predict")
        targets_map = missing & predict
    offset = float(np.mean(z[observed]))
    centred = np.where(observed, z - offset, 0.0)
    mean = np.where(missing, np.nan, z)
    sd = np.zeros(shape)
    iy, ix = np.indices(shape)
    largest = 0
    cores = [(r0, c0) for r0 in range(0, ny, tile) for c0 in range(0, nx, tile)
             if targets_map[r0:r0 + tile, c0:c0 + tile].any()]
    if progress is not None:
        progress(0, len(cores))
    with one_blas_thread():
        for done, (r0, c0) in enumerate(cores, start=1):
            core = np.s_[r0:r0 + tile, c0:c0 + tile]
            targets = targets_map[core]
            m = margin
            while True:
                win = np.s_[max(r0 - m, 0):r0 + tile + m, max(c0 - m, 0):c0 + tile + m]
                obs = observed[win]
                whole = win[0].start == 0 and win[1].start == 0 and \
                    r0 + tile + m >= ny and c0 + tile + m >= nx
                if obs.sum() >= min_observed or whole:
                    break
                m *= 2
            oy, ox = iy[win][obs], ix[win][obs]
            if oy.size > max_observed:
                keep = nearest_to_core(oy, ox, core[0], core[1], spacing, max_observed)
                oy, ox = oy[keep], ox[keep]
            ty, tx = iy[core][targets], ix[core][targets]
            k_oo = table[oy[:, None] - oy[None, :] + ny - 1, ox[:, None] - ox[None, :] + nx - 1]
            k_ot = table[oy[:, None] - ty[None, :] + ny - 1, ox[:, None] - tx[None, :] + nx - 1]
            k_oo[np.diag_indices_from(k_oo)] += noise_variance
            factor = scipy.linalg.cho_factor(k_oo, lower=True, check_finite=False)
            alpha = scipy.linalg.cho_solve(factor, centred[oy, ox], check_finite=False)
            half = scipy.linalg.solve_triangular(factor[0], k_ot, lower=True,
                                                 check_finite=False)
            mean[ty, tx] = offset + k_ot.T @ alpha
            sd[ty, tx] = np.sqrt(np.clip(variance - np.sum(half * half, axis=0), 0.0, None))
            largest = max(largest, int(oy.size))
            if progress is not None:
                progress(done, len(cores))
    return LocalFill(mean=mean, sd=sd, missing=missing, tiles=len(cores), largest_window=largest,
                     seconds=time.perf_counter() - start)
