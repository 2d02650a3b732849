r"""The Cholesky draw of eq 10 on a 2-D grid by Whittle's block Levinson recursion.

On a regular grid of shape ``(ny, nx)`` in row-major order, the covariance
:math:`\mathbf R` of a stationary field is block Toeplitz: the covariance of rows ``i`` and
``j`` is an ``(nx, nx)`` block that depends on ``j - i`` alone. The rows are then a
stationary vector sequence, and Whittle's (1963) multivariate Levinson-Durbin recursion
gives, row by row, the coefficients of each row's best linear prediction from the rows
before it and the covariance :math:`\mathbf V_k` of what is left (the innovation):

.. math::
    \mathbf z_k = \sum_{i=1}^{k} \mathbf A_{k,i}\,\mathbf z_{k-i}
        + \operatorname{chol}(\mathbf V_k)\,\boldsymbol\varepsilon_k .

This is :math:`\mathbf z = \mathbf L\boldsymbol\varepsilon` with :math:`\mathbf L` the lower
Cholesky factor of :math:`\mathbf R` itself (its block rows are the innovations
representation, and the factor is unique), so the same noise gives the dense Cholesky draw
of :mod:`roughgp.sampling.grid_sampler` to rounding, in about
:math:`2 n_y^2 n_x^3` flops instead of :math:`N^3/3` (64 x 64 points: 2.1e9 against 2.3e10).
Exact like the dense factor; nothing is approximated. The recursion loses more digits than
LAPACK's dense factorisation on a badly conditioned covariance: measured, :math:`\mathbf L
\mathbf L^\top` reproduces :math:`\mathbf R` to 1.9e-14 of its largest entry for figure 3's
first honing step on 32 x 32 points (the dense factor: 2.5e-15) and to 1.2e-11 for a Matérn
3/2 ACVF with :math:`\lambda` = 300 on 40 x 40 points (dense: 1.8e-15), far below any noise
a draw carries (``tests/sampling/test_block_levinson.py`` holds the paper's kernels and a
Matérn 5/2 to 1e-12). Where an innovation covariance is not numerically positive definite
(where the dense factorisation may need a jitter), :func:`factorise` returns None and the
caller takes the dense route with its jitter policy.

Every product, solve and factorisation here goes through numpy's LAPACK and none through
SciPy's: numpy and SciPy each bundle an OpenBLAS with its own thread pool, and alternating
between the two in a loop of small calls made the 64 x 64 recursion of figure 3's first
honing step take 0.9-1.0 s instead of 0.1-0.2 s on the 2-core machine (the pools' threads
contend for the cores; measured 2026-12-03, default thread settings).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from roughgp.common.threads import single_blas_thread

__all__ = ["BlockFactor", "factorise", "flops", "worthwhile"]

#: A row of the recursion costs Python and LAPACK call overhead worth about this many flops.
ROW_OVERHEAD_FLOPS = 1e6


def flops(shape) -> float:
    """The recursion's cost on a 2-D grid ``(ny, nx)``: ``2 ny^2 nx^3`` flops plus
    :data:`ROW_OVERHEAD_FLOPS` a row."""
    ny, nx = (int(n) for n in shape)
    return 2.0 * ny**2 * nx**3 + ROW_OVERHEAD_FLOPS * ny


def worthwhile(shape) -> bool:
    """Whether the recursion costs less than half a dense factorisation (``N^3 / 3`` flops)
    of this 2-D grid; a profile or a grid of a few rows is factorised densely."""
    if len(shape) != 2 or shape[0] < 2:
        return False
    return flops(shape) < math.prod(int(n) for n in shape) ** 3 / 6


@dataclass
class BlockFactor:
    """The Cholesky factor of a block-Toeplitz grid covariance in its recursive form.

    Attributes:
        shape: ``(ny, nx)``.
        predictors: ``predictors[k - 1]`` is ``[A_{k,1} | ... | A_{k,k}]``, shape
            ``(nx, k nx)``, for ``k = 1 .. ny - 1``.
        roots: ``roots[k]`` is the lower Cholesky factor of ``V_k``, ``(nx, nx)``.
    """

    shape: tuple
    predictors: list
    roots: list

    @property
    def nbytes(self) -> int:
        return sum(a.nbytes for a in self.predictors) + sum(r.nbytes for r in self.roots)

    @single_blas_thread
    def __matmul__(self, noise) -> np.ndarray:
        """``L @ noise`` for ``noise`` of shape ``(N, n_samples)``, row by row (so a draw is
        ``factor @ noise`` whether the factor is this or a dense array)."""
        ny, nx = self.shape
        e = np.asarray(noise, dtype=np.float64).reshape(ny, nx, -1)
        back = np.empty((ny * nx, e.shape[-1]))  # row k at block ny - 1 - k: z_{k-1}..z_0 follow
        for k in range(ny):
            row = self.roots[k] @ e[k]
            if k:
                row += self.predictors[k - 1] @ back[(ny - k) * nx:]
            back[(ny - 1 - k) * nx:(ny - k) * nx] = row
        return back.reshape(ny, nx, -1)[::-1].reshape(ny * nx, -1)


def _root(matrix):
    try:
        return np.linalg.cholesky(matrix)
    except np.linalg.LinAlgError:
        return None


@single_blas_thread
def factorise(table, shape) -> BlockFactor | None:
    """The :class:`BlockFactor` of the grid covariance of lag ``table`` (the ACVF on the
    ``(2 ny - 1, 2 nx - 1)`` lag grid, as :func:`roughgp.sampling.grid_covariance` gathers
    it), or None where an innovation covariance does not factorise."""
    ny, nx = shape
    offsets = np.arange(nx)
    # Gamma(h) = Cov(z_{t+h}, z_t): entry [a, b] is the covariance at lag (-h, b - a)
    gamma = table[ny - 1 - np.arange(ny)][:, offsets[None, :] - offsets[:, None] + nx - 1]
    down = np.concatenate(gamma[:0:-1]) if ny > 1 else np.empty((0, nx))  # Gamma(ny-1)..(1)
    # The backward recursion needs no work of its own: J Gamma(h) J = Gamma(h)^T for any
    # stationary field (J reverses the order along x), so the backward predictor and error
    # covariance of order p are J A_{p,i} J and J V_p J.
    forward = np.empty((nx, 0))  # [A_{p,1} | ... | A_{p,p}]
    # forward[::-1, ::-1] = [J A_p J | .. | J A_1 J], kept as a contiguous copy (a product with
    # the reversed view is slower than with a copy)
    mirrored = forward
    v = gamma[0]
    predictors, roots = [], []
    for p in range(ny):
        root = _root(v)
        if root is None:
            return None
        roots.append(root)
        if p == ny - 1:
            break
        delta = gamma[p + 1] - forward @ down[(ny - 1 - p) * nx:]
        # the gain delta U^{-1} with U = J V J: (J V^{-1} J delta^T)^T
        gain = np.ascontiguousarray(np.linalg.solve(v, delta.T[::-1])[::-1].T)
        forward = np.hstack([forward - gain @ mirrored, gain])
        mirrored = np.ascontiguousarray(forward[::-1, ::-1])
        predictors.append(forward)
        v = v - gain @ delta.T
        v = 0.5 * (v + v.T)
    return BlockFactor(tuple(shape), predictors, roots)
