r"""Fit eq 18 plus noise to the valid points of a height map with holes (beyond the paper).

:func:`roughgp.filling.global_fill.fill_gaps` needs the kernel and the noise variance; a measurement
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
measured heights. The optimum is searched by L-BFGS-B with the likelihood's gradient
(:class:`BlockLikelihood`), in the log scales and the angle, within bounds set by the data
(the variances from ``1e-4`` and ``1e-8`` to ``100`` and ``10`` times the heights' variance,
the lengthscales from a twentieth of the spacing to fifty blocks), from the best of a small
grid of starts (four groove directions, two lengthscale ratios). The factorisations are
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
import scipy.optimize

from roughgp.common.checks import as_generator, boolean_map, check_integer
from roughgp.common.grid import centred_lags, normalize
from roughgp.common.numerics import perturbed_start
from roughgp.common.threads import one_blas_thread
from roughgp.gp import acvf as _acvf
from roughgp.models.surfaces import GrooveParameters
from roughgp.sampling.grid_sampler import covariance_index

__all__ = ["BlockFit", "BlockLikelihood", "PARAMETERS", "fit_ground_to_valid_points"]

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
        """The fitted kernel, for :func:`roughgp.filling.global_fill.fill_gaps`: eq 18's
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


PARAMETERS = ("variance", "lambda_a", "lambda_b", "angle", "noise_variance")
r"""The order of the unconstrained vector ``u`` of :class:`BlockLikelihood`: the logarithms of
:math:`\sigma_k^2, \lambda_a, \lambda_b`, the angle :math:`\phi` itself, the logarithm of
:math:`\sigma^2`."""

_ANGLE = PARAMETERS.index("angle")
_STEP = 1e-6  # central-difference step of the ACVF table in log lengthscale and angle


class BlockLikelihood:
    r"""The block composite log-likelihood :math:`\ell_c` (module docstring) of the measured
    points of the chosen blocks, and its gradient, as functions of
    ``u = (log sigma_k^2, log lambda_a, log lambda_b, phi, log sigma^2)`` (:data:`PARAMETERS`).

    The covariance of every block is gathered from one table of the ACVF on the lags a block's
    points have. The gradient is that of eq 12 per block,
    :math:`\partial\ell/\partial\theta = \tfrac12\operatorname{tr}\big((\boldsymbol\alpha
    \boldsymbol\alpha^\top - \mathbf K^{-1})\,\partial\mathbf K/\partial\theta\big)`,
    :math:`\boldsymbol\alpha = \mathbf K^{-1}\mathbf y`, from one Cholesky factor and its
    inverse per block (about three factorisations' work, against six for a finite-difference
    gradient of five parameters). The trace is summed per lag (the weights of
    :math:`\boldsymbol\alpha\boldsymbol\alpha^\top - \mathbf K^{-1}` binned by the lag of
    each pair), so each parameter costs one dot product with the table's derivative; the
    derivatives in the lengthscales and the angle are central differences of the table
    (step ``1e-6``), those in the two variances are exact.
    """

    def __init__(self, z, valid, blocks, block, spacing, nu=0.5):
        self.nu = nu
        self._lags = centred_lags((2 * block - 1, 2 * block - 1), spacing)
        index = covariance_index((block, block))
        self._terms = []
        for r, c in blocks:
            inside = valid[r:r + block, c:c + block].reshape(-1)
            self._terms.append((index[np.ix_(inside, inside)],
                                z[r:r + block, c:c + block].reshape(-1)[inside]))

    def table(self, variance, lambda_a, lambda_b, angle):
        """The ACVF (eq 18, or its Matérn variant) on the lags of a block, flattened."""
        scales = np.array([lambda_a, lambda_b])
        if self.nu == 0.5:
            values = _acvf.rotated_exponential(self._lags, variance, scales, angle)
        else:
            values = _acvf.rotated_matern(self._lags, variance, scales, angle, self.nu)
        return np.asarray(values, dtype=np.float64).reshape(-1)

    @staticmethod
    def natural(u) -> dict:
        """``u`` -> dict name -> value (natural units; the angle not wrapped)."""
        u = np.asarray(u, dtype=np.float64)
        return {name: (float(u[k]) if k == _ANGLE else math.exp(float(u[k])))
                for k, name in enumerate(PARAMETERS)}

    @staticmethod
    def unconstrained(values) -> np.ndarray:
        """dict name -> value -> ``u``."""
        return np.array([float(values[name]) if k == _ANGLE else math.log(float(values[name]))
                         for k, name in enumerate(PARAMETERS)])

    def value(self, u) -> float:
        r""":math:`\ell_c` at ``u``; ``-inf`` where a block's covariance is not positive
        definite."""
        return self._evaluate(u, gradient=False)[0]

    def value_and_gradient(self, u):
        """``(ell_c, d ell_c / d u)`` at ``u``; ``(-inf, zeros)`` where a block's covariance is
        not positive definite."""
        return self._evaluate(u, gradient=True)

    def _evaluate(self, u, gradient):
        p = self.natural(u)
        table = self.table(p["variance"], p["lambda_a"], p["lambda_b"], p["angle"])
        noise = p["noise_variance"]
        total, binned, trace = 0.0, np.zeros(table.size), 0.0
        for idx, y in self._terms:
            cov = table[idx]
            cov[np.diag_indices_from(cov)] += noise
            factor, info = scipy.linalg.lapack.dpotrf(cov, lower=1, clean=0, overwrite_a=1)
            if info != 0:
                return -math.inf, np.zeros(len(PARAMETERS))
            alpha = scipy.linalg.cho_solve((factor, True), y, check_finite=False)
            total -= 0.5 * (y @ alpha + y.size * _LOG_2PI) + np.sum(np.log(np.diag(factor)))
            if gradient:
                inverse, info = scipy.linalg.lapack.dpotri(factor, lower=1, overwrite_c=1)
                if info != 0:
                    return -math.inf, np.zeros(len(PARAMETERS))
                inverse = np.tril(inverse) + np.tril(inverse, -1).T
                weights = np.outer(alpha, alpha) - inverse
                binned += np.bincount(idx.ravel(), weights=weights.ravel(), minlength=table.size)
                trace += float(np.trace(weights))
        if not gradient:
            return float(total), None
        grad = np.empty(len(PARAMETERS))
        grad[0] = 0.5 * binned @ table                         # d table / d log sigma_k^2
        for k, name in ((1, "lambda_a"), (2, "lambda_b"), (_ANGLE, "angle")):
            up, down = dict(p), dict(p)
            if k == _ANGLE:
                up[name], down[name] = p[name] + _STEP, p[name] - _STEP
            else:
                up[name], down[name] = p[name] * math.exp(_STEP), p[name] * math.exp(-_STEP)
            derivative = (self.table(p["variance"], up["lambda_a"], up["lambda_b"], up["angle"])
                          - self.table(p["variance"], down["lambda_a"], down["lambda_b"],
                                       down["angle"])) / (2 * _STEP)
            grad[k] = 0.5 * binned @ derivative
        grad[4] = 0.5 * trace * noise                           # d K / d log sigma^2
        return float(total), grad


def fit_ground_to_valid_points(z, *, spacing=1.0, mask=None, block=24, n_blocks=12,
                               min_valid=0.5, seed=None, maxiter=500, nu=0.5,
                               start=None) -> BlockFit:
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
        start: optional :class:`BlockFit` (on these blocks, e.g. eq 18's when its Matérn
            variant is fitted next): its optimum joins the starts, and the best two starts
            are optimised instead of three (two thirds of a Matérn fit's work).

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
        mask = boolean_map(mask, z.shape)
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
    scale = (d / 20.0, 50.0 * extent)
    ranges = {"variance": (1e-4 * var, 100.0 * var), "lambda_a": scale, "lambda_b": scale,
              "noise_variance": (1e-8 * var, 10.0 * var)}
    bounds = [(None, None) if name == "angle" else tuple(math.log(v) for v in ranges[name])
              for name in PARAMETERS]
    likelihood = BlockLikelihood(centred, valid, blocks, block, spacing, nu)
    starts = [likelihood.unconstrained(
                  {"variance": 0.9 * var, "lambda_a": extent / 4, "lambda_b": extent / 4 / ratio,
                   "angle": angle, "noise_variance": 0.1 * var})
              for angle in (0.0, math.pi / 4, math.pi / 2, -math.pi / 4) for ratio in (1.5, 6.0)]
    # eq 18 (nu = 0.5) from the best start; the smoother Matern profiles, whose covariances
    # are near-singular at short lengthscales, can stop in a poor optimum from one start (2 of
    # 5 seeded test surfaces did): from the best three, keeping the best optimum.
    n_optimised = 1 if nu == 0.5 else 3
    if start is not None:
        if not isinstance(start, BlockFit):
            raise ValueError(f"start must be a BlockFit, got {type(start).__name__}")
        g = start.groove
        lows, highs = zip(*(b if b != (None, None) else (-math.inf, math.inf) for b in bounds))
        starts.append(np.clip(likelihood.unconstrained(
            {"variance": g.variance, "lambda_a": g.lengthscales[0],
             "lambda_b": g.lengthscales[1], "angle": g.angle,
             "noise_variance": start.noise_variance}), lows, highs))
        n_optimised = 2
    with one_blas_thread():
        ranked = sorted(starts, key=likelihood.value, reverse=True)
        optima = [_maximise(likelihood, u0, bounds, maxiter) for u0 in ranked[:n_optimised]]
    best = min(optima, key=lambda result: result.fun)
    if not best.fun < 1e300:
        raise ValueError("the block covariance is not positive definite at any start: the "
                         "measured heights may hold steps or constant patches")
    found = likelihood.natural(best.x)
    lam_a, lam_b, angle = found["lambda_a"], found["lambda_b"], found["angle"]
    if lam_a < lam_b:
        lam_a, lam_b, angle = lam_b, lam_a, angle + math.pi / 2
    angle = (angle + math.pi / 2) % math.pi - math.pi / 2
    groove = GrooveParameters(found["variance"], (lam_a, lam_b), angle)
    n_points = int(sum(valid[r:r + block, c:c + block].sum() for r, c in blocks))
    return BlockFit(groove=groove, noise_variance=found["noise_variance"], mean=mean,
                    log_likelihood=float(-best.fun), blocks=blocks, n_points=n_points, nu=nu)


def _maximise(likelihood, u0, bounds, maxiter):
    """L-BFGS-B on ``-ell_c`` with its gradient, within ``bounds`` (the result of
    ``scipy.optimize.minimize``)."""
    def objective(u):
        value, grad = likelihood.value_and_gradient(u)
        if not math.isfinite(value):        # not positive definite: a wall the search backs off
            return 1e300, np.zeros_like(grad)
        return -value, -grad

    lows, highs = (np.array([np.nan if b is None else b for b in side], dtype=float)
                   for side in zip(*bounds))
    return scipy.optimize.minimize(objective, perturbed_start(u0, lows, highs), jac=True,
                                   method="L-BFGS-B", bounds=bounds,
                                   options={"maxiter": int(maxiter)})
