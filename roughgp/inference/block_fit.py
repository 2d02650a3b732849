r"""Fit eq 18 plus noise to the valid points of a height map with holes (beyond the paper).

:func:`roughgp.beyond.gap_filling.fill_gaps` needs the kernel and the noise variance; a measurement
with unmeasured points comes without them. :func:`fit_ground_to_valid_points` estimates
:math:`\sigma_k^2, \lambda_a, \lambda_b, \phi` (eq 18) and :math:`\sigma^2` (eq 8) from the
measured points alone by **maximum block composite likelihood**: the grid is cut into
non-overlapping ``block x block`` windows, ``n_blocks`` of them are chosen at random (seeded)
among those with at least ``min_valid`` of their points measured, and the objective is the sum
over the chosen blocks of the exact Gaussian log-likelihood (eq 12) of each block's measured
points (a dense Cholesky factor per block; the holes are simply left out of the covariance):

.. math::
    \ell_c(\boldsymbol\alpha) = \sum_b \log \mathcal N\!\left(\mathbf y_b - \bar y \mid
    \mathbf 0,\ \mathbf R_b(\boldsymbol\alpha) + \sigma^2\mathbf I\right).

Each term is a true marginal likelihood, so the estimate is consistent; it ignores the
correlation between blocks, so it is less efficient than the full likelihood, most for
lengthscales beyond the block size. The constant mean :math:`\bar y` is the mean of all
measured heights. The optimum is searched by L-BFGS-B with finite-difference gradients
(:func:`roughgp.inference.posterior.maximum_a_posteriori`, flat priors in the log scales and
the angle; about a quarter of Nelder-Mead's evaluations for the same optimum) from the best of
a small grid of starts (four groove directions, two lengthscale ratios). The factorisations are
small (at most ``block**2`` rows), so they run on one BLAS thread: several threads gain nothing
on them and, on a busy machine, make them many times slower. :math:`(\lambda_a, \lambda_b, \phi)` and
:math:`(\lambda_b, \lambda_a, \phi + \pi/2)` are the same ACVF: the result is reported with
:math:`\lambda_a \ge \lambda_b` and :math:`\phi \in [-\pi/2, \pi/2)`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import scipy.linalg
from threadpoolctl import threadpool_limits

from roughgp.common.checks import as_generator, check_integer
from roughgp.common.grid import centred_lags, normalize
from roughgp.gp import acvf as _acvf
from roughgp.inference.posterior import (
    LogUniform,
    Parameter,
    PosteriorModel,
    UniformAngle,
    maximum_a_posteriori,
)
from roughgp.models.surfaces import GrooveParameters
from roughgp.sampling.grid_sampler import covariance_index

__all__ = ["BlockFit", "fit_ground_to_valid_points"]

_LOG_2PI = math.log(2.0 * math.pi)


@dataclass(frozen=True)
class BlockFit:
    """The result of :func:`fit_ground_to_valid_points`.

    Attributes:
        groove: the fitted eq 18 hyperparameters (``lambda_a >= lambda_b``).
        noise_variance: the fitted :math:`\\sigma^2` of eq 8.
        mean: the constant mean removed (mean of the measured heights).
        log_likelihood: the block composite log-likelihood at the optimum.
        blocks: ``(row, col)`` of the top-left corner of each block used.
        n_points: measured points in the blocks used.
        nu: the Matérn smoothness of the radial profile (0.5: eq 18 itself).
    """

    groove: GrooveParameters
    noise_variance: float
    mean: float
    log_likelihood: float
    blocks: tuple
    n_points: int
    nu: float = 0.5

    @property
    def kernel(self):
        """The fitted kernel, for :func:`roughgp.beyond.gap_filling.fill_gaps`: eq 18's
        ``RotatedExponentialKernel`` (``nu = 0.5``) or the function of lags of
        :func:`roughgp.gp.acvf.rotated_matern`."""
        if self.nu == 0.5:
            return self.groove.kernel()
        g, nu = self.groove, self.nu
        return lambda lags: _acvf.rotated_matern(lags, g.variance, np.asarray(g.lengthscales),
                                                  g.angle, nu)


def _choose_blocks(valid, block, n_blocks, min_valid, rng):
    ny, nx = valid.shape
    corners = [(r, c) for r in range(0, ny - block + 1, block)
               for c in range(0, nx - block + 1, block)
               if valid[r:r + block, c:c + block].mean() >= min_valid]
    if not corners:
        raise ValueError(f"no {block} x {block} block of z has at least {min_valid:.0%} of its "
                         f"points measured; use a smaller block or a lower min_valid")
    picked = rng.choice(len(corners), size=min(n_blocks, len(corners)), replace=False)
    return tuple(corners[k] for k in sorted(picked))


def _block_log_likelihood(z, valid, blocks, block, spacing, nu=0.5):
    """``loglik(params)``: the composite log-likelihood of the measured points of the blocks."""
    lags = centred_lags((2 * block - 1, 2 * block - 1), spacing)
    index = covariance_index((block, block))
    terms = []
    for r, c in blocks:
        inside = valid[r:r + block, c:c + block].reshape(-1)
        terms.append((index[np.ix_(inside, inside)],
                      z[r:r + block, c:c + block].reshape(-1)[inside]))

    def loglik(p):
        scales = np.array([p["lambda_a"], p["lambda_b"]])
        table = (_acvf.rotated_exponential(lags, p["variance"], scales, p["angle"])
                 if nu == 0.5 else
                 _acvf.rotated_matern(lags, p["variance"], scales, p["angle"], nu)).reshape(-1)
        total = 0.0
        for idx, y in terms:
            cov = table[idx]
            cov[np.diag_indices_from(cov)] += p["noise_variance"]
            try:
                factor = scipy.linalg.cho_factor(cov, lower=True, check_finite=False)
            except np.linalg.LinAlgError:
                raise ValueError("covariance not positive definite") from None
            alpha = scipy.linalg.cho_solve(factor, y, check_finite=False)
            total -= 0.5 * (y @ alpha + y.size * _LOG_2PI) + np.sum(np.log(np.diag(factor[0])))
        return float(total)

    return loglik


def fit_ground_to_valid_points(z, *, spacing=1.0, mask=None, block=24, n_blocks=12,
                               min_valid=0.5, seed=None, maxiter=500, nu=0.5) -> BlockFit:
    """Fit eq 18 plus white noise (eq 8) to the measured points of ``z`` (module docstring).

    Args:
        z: height map ``z[iy, ix]``, NaN where not measured.
        spacing: grid spacing, scalar or ``(dy, dx)``; the lengthscales come in its unit.
        mask: optional boolean array like ``z``; True marks points to leave out as well.
        block: block side in points (>= 4); one likelihood evaluation factorises
            ``n_blocks`` matrices of at most ``block**2`` rows.
        n_blocks: blocks used (>= 1; fewer where fewer qualify).
        min_valid: in (0, 1]: the smallest measured share of a usable block.
        seed: int, None or Generator: which blocks are used.
        maxiter: L-BFGS-B iterations (at most).
        nu: 0.5 (eq 18, the default), 1.5 or 2.5: the Matérn smoothness of the radial profile
            (:func:`roughgp.gp.acvf.rotated_matern`; beyond the paper, for smooth surfaces).

    Returns:
        :class:`BlockFit`.
    """
    z = np.asarray(z, dtype=np.float64)
    if z.ndim != 2:
        raise ValueError(f"z must be a 2-D height map z[iy, ix], got shape {z.shape}")
    if np.any(np.isinf(z)):
        raise ValueError("z must not hold inf; mark unmeasured points with NaN or in mask")
    valid = ~np.isnan(z)
    if mask is not None:
        mask = np.asarray(mask)
        if mask.dtype != bool or mask.shape != z.shape:
            raise ValueError(f"mask must be a boolean array of the shape of z {z.shape}, got "
                             f"{mask.dtype} of shape {mask.shape}")
        valid &= ~mask
    block = check_integer("block", block, 4)
    if block > min(z.shape):
        raise ValueError(f"block must be in [4, {min(z.shape)}] (the shorter side of z), "
                         f"got {block}")
    n_blocks = check_integer("n_blocks", n_blocks, 1)
    if not (isinstance(min_valid, (int, float)) and 0 < min_valid <= 1):
        raise ValueError(f"min_valid must be in (0, 1], got {min_valid!r}")
    maxiter = check_integer("maxiter", maxiter, 1)
    if nu not in (0.5, 1.5, 2.5):
        raise ValueError(f"nu must be 0.5 (eq 18), 1.5 or 2.5, got {nu!r}")
    _, spacing = normalize(z.shape, spacing)
    blocks = _choose_blocks(valid, block, n_blocks, min_valid, as_generator(seed))
    mean = float(np.mean(z[valid]))
    centred = np.where(valid, z - mean, 0.0)
    var = float(np.mean(centred[valid] ** 2))
    if not var > 0:
        raise ValueError("the measured heights of z are constant")

    d, extent = float(spacing.min()), float(block * spacing.max())
    scale = LogUniform(d / 20.0, 50.0 * extent)
    params = (Parameter("variance", LogUniform(1e-4 * var, 100.0 * var)),
              Parameter("lambda_a", scale), Parameter("lambda_b", scale),
              Parameter("angle", UniformAngle(math.pi)),
              Parameter("noise_variance", LogUniform(1e-8 * var, 10.0 * var)))
    loglik = _block_log_likelihood(centred, valid, blocks, block, spacing, nu)
    model = PosteriorModel(params, loglik)
    starts = [{"variance": 0.9 * var, "lambda_a": extent / 4, "lambda_b": extent / 4 / ratio,
               "angle": angle, "noise_variance": 0.1 * var}
              for angle in (0.0, math.pi / 4, math.pi / 2, -math.pi / 4) for ratio in (1.5, 6.0)]
    # eq 18 (nu = 0.5) from the best start; the smoother Matern profiles, whose covariances
    # are near-singular at short lengthscales, can stop in a poor optimum from one start (2 of
    # 5 seeded test surfaces did): from the best three, keeping the best optimum.
    n_optimised = 1 if nu == 0.5 else 3
    with threadpool_limits(limits=1, user_api="blas"):
        ranked = sorted(starts, key=lambda s: model.log_posterior(model.to_unconstrained(s)),
                        reverse=True)
        found = max((maximum_a_posteriori(model, s, maxiter=maxiter, method="L-BFGS-B")
                     for s in ranked[:n_optimised]),
                    key=lambda f: model.log_posterior(model.to_unconstrained(f)))
    lam_a, lam_b, angle = found["lambda_a"], found["lambda_b"], found["angle"]
    if lam_a < lam_b:
        lam_a, lam_b, angle = lam_b, lam_a, angle + math.pi / 2
    angle = (angle + math.pi / 2) % math.pi - math.pi / 2
    groove = GrooveParameters(found["variance"], (lam_a, lam_b), angle)
    n_points = int(sum(valid[r:r + block, c:c + block].sum() for r, c in blocks))
    return BlockFit(groove=groove, noise_variance=found["noise_variance"], mean=mean,
                    log_likelihood=loglik(found), blocks=blocks, n_points=n_points, nu=nu)
