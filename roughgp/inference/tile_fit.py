r"""Local likelihood: eq 18 fitted on each tile of a map, with each fit's own uncertainty
(beyond the paper; issue 40, items 3 and 4; the paper's future work, section 4).

A map is cut into ``m x n`` tiles (:func:`roughgp.common.tiling.tile_slices`); on each tile,
eq 18 plus noise is fitted by the debiased spatial Whittle likelihood of its measured points
(:func:`~roughgp.inference.whittle_fit.fit_whittle`), and the fit's covariance is the sandwich
:math:`H^{-1} J H^{-1}` (:func:`~roughgp.inference.whittle_fit.robust_covariance`: the inverse
observed information alone understates the spread about twofold). This is the local
likelihood of convoSPAT (Risser & Calder 2017, J. Stat. Softw. 81(14)) on disjoint windows:
the tiles share no point, so their estimates are independent given the surface, which the
random-effects pooling of :mod:`roughgp.inference.random_effects` needs.

Parameters are kept as ``u = (log variance, log lambda_a, log lambda_b, angle, log noise)``
per tile, ``lambda_a >= lambda_b``, angle in radians in ``[-pi/2, pi/2)``; tile centres in the
map's length unit from its first point (``x`` along columns, ``y`` along rows).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from roughgp.common.checks import as_generator, check_integer
from roughgp.common.grid import normalize
from roughgp.common.tiling import tile_slices
from roughgp.inference.whittle_fit import MIN_POINTS, fit_whittle, robust_covariance

__all__ = ["PARAMETERS", "TileFits", "fit_tiles"]

#: the entries of ``u`` per tile
PARAMETERS = ("log variance", "log lambda_a", "log lambda_b", "angle", "log noise")


@dataclass(frozen=True)
class TileFits:
    """Eq 18 fitted on each tile of a map (:func:`fit_tiles`).

    Attributes:
        tiles: ``(m, n)``.
        centres_y, centres_x: the tiles' centres (shapes ``(m,)`` and ``(n,)``), in the
            spacing's unit from the map's first point.
        estimates: ``(m, n, 5)``, ``u`` per tile (:data:`PARAMETERS`); NaN for a tile with
            too few measured points.
        covariances: ``(m, n, 5, 5)``, the sandwich covariance of each tile's ``u`` (NaN
            where a tile does not determine it).
        n_points: ``(m, n)``, the measured points of each tile.
        shape, spacing: of the map.
        nu: the Matérn smoothness fitted (0.5: eq 18).
    """

    tiles: tuple
    centres_y: np.ndarray
    centres_x: np.ndarray
    estimates: np.ndarray
    covariances: np.ndarray
    n_points: np.ndarray
    shape: tuple
    spacing: tuple
    nu: float = 0.5

    def standard_errors(self) -> np.ndarray:
        """``(m, n, 5)``: the square roots of the covariances' diagonals."""
        diagonal = np.diagonal(self.covariances, axis1=-2, axis2=-1)
        return np.sqrt(np.where(diagonal > 0, diagonal, np.nan))

    def pooling_variances(self) -> np.ndarray:
        """``(m, n, 5)``: each tile's variance of ``u`` for pooling, taken as one precision per
        measured point for all tiles (the median over the tiles of variance x points, divided
        by the tile's points).

        Why not each tile's own sandwich variance: it is computed at the tile's own estimate,
        and a tile whose variance and lengths came out short also gets a short standard error
        (fewer correlated points per length), so weighting by it pulls the pooled value down:
        on 4 x 4 tiles of 64 x 64 points (lambda_a 8) the pooled log variance fell 0.05 to
        0.10 below the truth while the tiles' plain mean was within 0.01. With the same
        precision per point the weights no longer depend on the estimates' errors."""
        diagonal = np.diagonal(self.covariances, axis1=-2, axis2=-1)
        points = np.where(self.n_points > 0, self.n_points, np.nan)[..., None]
        per_point = np.nanmedian(np.where(diagonal > 0, diagonal, np.nan) * points,
                                 axis=(0, 1))
        return np.where(np.isfinite(diagonal) & (diagonal > 0), per_point / points, np.nan)


def fit_tiles(z, spacing=1.0, *, tiles=(2, 2), nu=0.5, n_draws=40, seed=0,
              device=None) -> TileFits:
    """Fit eq 18 plus noise on each of ``tiles = (m, n)`` tiles of ``z`` (module docstring).

    Args:
        z: the form-removed heights ``z[iy, ix]``, NaN where not measured.
        spacing: scalar or ``(dy, dx)``.
        tiles: ``(m, n)``; each tile at least :data:`~roughgp.inference.whittle_fit.MIN_POINTS`
            rows and columns.
        nu: 0.5 (eq 18), 1.5 or 2.5.
        n_draws: the simulated scores per tile of the sandwich covariance (>= 10).
        seed: of those draws; the same seed, the same covariances.
        device: as :func:`~roughgp.inference.whittle_fit.fit_whittle`.
    """
    z = np.asarray(z, dtype=np.float64)
    if z.ndim != 2:
        raise ValueError(f"z must be a 2-D height map z[iy, ix], got shape {z.shape}")
    check_integer("n_draws", n_draws, 10)
    _, spacing = normalize(z.shape, spacing)
    slices = tile_slices(z.shape, tiles)
    m, n = (int(t) for t in tiles)
    rng = as_generator(seed)
    estimates = np.full((m, n, 5), np.nan)
    covariances = np.full((m, n, 5, 5), np.nan)
    n_points = np.zeros((m, n), dtype=int)
    for index, (rows, cols) in enumerate(slices):
        i, j = divmod(index, n)
        tile = z[rows, cols]
        valid = np.isfinite(tile)
        tile_seed = int(rng.integers(2**63))
        n_points[i, j] = int(valid.sum())
        if valid.sum() < MIN_POINTS * MIN_POINTS or np.ptp(tile[valid]) == 0:
            continue
        fit = fit_whittle(tile, spacing=spacing, nu=nu, device=device)
        estimates[i, j] = fit.u
        covariances[i, j] = robust_covariance(fit, valid, spacing, n_draws=n_draws,
                                              seed=tile_seed, device=device)
    centres_y = np.array([(s.start + s.stop - 1) / 2 * spacing[0]
                          for s, _ in slices[::n]])
    centres_x = np.array([(s.start + s.stop - 1) / 2 * spacing[1] for _, s in slices[:n]])
    return TileFits((m, n), centres_y, centres_x, estimates, covariances, n_points,
                    tuple(z.shape),
                    tuple(float(d) for d in spacing), nu)
