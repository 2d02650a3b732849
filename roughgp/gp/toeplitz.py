r"""Exact Gaussian log-likelihood of a profile on a regular grid, in :math:`O(n^2)`.

A stationary process sampled on a regular 1-D grid has a symmetric Toeplitz covariance
(:math:`K_{st} = r_{|s-t|}`, R of eq 10 plus the noise of eq 8 on the diagonal). Its dense
Cholesky factorisation costs :math:`O(n^3)`; the structure gives the same numbers in
:math:`O(n^2)`. Used by :mod:`roughgp.models.arma` (section 2.3) and :mod:`roughgp.inference.fitting`
(section 3.3).

Likelihood and gradient
-----------------------
The covariance :math:`K` is a symmetric Toeplitz matrix with first column :math:`r` (the
ACVF at the lags ``h * spacing``, the noise variance added to :math:`r_0`). :func:`toeplitz_log_likelihood` evaluates

.. math::
    \log p(z) = -\tfrac12 z^\top K^{-1} z - \tfrac12\log|K| - \tfrac n2\log 2\pi

exactly in :math:`O(n^2)`: one Levinson-Durbin recursion (SciPy's compiled Levinson solver)
solves the Yule-Walker system of order :math:`n-1`; its reflection coefficients
:math:`\kappa_m` give the prediction-error variances :math:`v_m = v_{m-1}(1-\kappa_m^2)` and
:math:`\log|K| = \sum_m \log v_m`, and its predictor gives the first column :math:`x` of
:math:`K^{-1}`. The Gohberg-Semencul formula
:math:`K^{-1} = x_0^{-1}[L(x)L(x)^\top - L(y)L(y)^\top]` (:math:`L(\cdot)` the lower-triangular
Toeplitz matrix of a column, :math:`y = (0, x_{n-1}, \dots, x_1)`) then gives
:math:`\alpha = K^{-1}z` with four FFT convolutions, and the exact gradient with respect to
the first column,

.. math::
    \frac{\partial \log p}{\partial r_h} = \tfrac12 w_h \Big(\sum_i \alpha_i\alpha_{i+h}
    - c_h\Big),\quad w_0 = 1,\ w_{h>0} = 2,

where :math:`c_h` is the sum of the :math:`h`-th diagonal of :math:`K^{-1}`; for
:math:`L(a)L(a)^\top` that sum is :math:`\sum_j (n-h-j)\,a_j a_{j+h}`, two FFT correlations.
So one likelihood-and-gradient evaluation costs one :math:`O(n^2)` recursion plus
:math:`O(n\log n)`. Where SciPy's private Levinson solver is missing, a Python
Durbin-Levinson loop (same numbers, slower) takes its place.

On a device
-----------
With ``device=`` (:mod:`roughgp.common.device`) the same numbers come from the dense route on that
device: :math:`K` gathered from :math:`r`, its Cholesky factor, and the gradient with respect
to :math:`r` by automatic differentiation through both (:math:`O(n^3)`). The recursion is
sequential and the dense route parallel: on a GPU the dense route is the faster one for the
profile lengths of section 3.3 (``benchmarks/device.py`` measures both).
"""

from __future__ import annotations

import math

import numpy as np
from scipy import fft as sp_fft

from roughgp.common.checks import check_finite
from roughgp.common.device import resolve as resolve_device

try:  # SciPy's compiled Levinson recursion (returns the reflection coefficients too)
    from scipy.linalg._solve_toeplitz import levinson as _scipy_levinson
except ImportError:  # pragma: no cover - fallback for a SciPy without the private module
    _scipy_levinson = None

__all__ = ["toeplitz_log_likelihood", "toeplitz_log_likelihood_terms", "dense_log_likelihood_terms"]


def _yule_walker_levinson(r):
    """``(phi, kappa)``: the order-(n-1) predictor and the reflection coefficients 1..n-1."""
    n = r.size
    if n == 1:
        return np.zeros(0), np.zeros(0)
    if _scipy_levinson is not None:
        a = np.concatenate((r[n - 2:0:-1], r[:n - 1]))
        phi, refl = _scipy_levinson(np.ascontiguousarray(a), np.ascontiguousarray(r[1:n]))
        return phi, refl[1:n]
    phi, v, kappas = np.zeros(0), r[0], np.empty(n - 1)  # pragma: no cover
    for m in range(n - 1):  # pragma: no cover
        kappa = (r[m + 1] - phi @ r[m:0:-1]) / v
        phi, v = np.r_[phi - kappa * phi[::-1], kappa], v * (1.0 - kappa * kappa)
        kappas[m] = kappa
    return phi, kappas  # pragma: no cover


def _conv(u_hat, v, n, nfft):
    """First ``n`` values of the linear convolution of u (given by its rfft) and v."""
    return sp_fft.irfft(u_hat * sp_fft.rfft(v, nfft), nfft)[:n]


def toeplitz_log_likelihood_terms(z, r, gradient):
    """``(loglik, grad or None)`` of a checked float64 profile ``z`` and ACVF values ``r`` by
    Levinson-Durbin and Gohberg-Semencul: the unchecked core of :func:`toeplitz_log_likelihood`."""
    n = z.size
    if not r[0] > 0:
        raise np.linalg.LinAlgError("covariance not positive definite (r[0] <= 0)")
    phi, kappa = _yule_walker_levinson(r)
    one_minus = 1.0 - kappa * kappa
    if not (np.all(np.isfinite(phi)) and np.all(one_minus > 0)):
        raise np.linalg.LinAlgError("covariance not positive definite (|kappa| >= 1)")
    log_v = math.log(r[0]) + np.concatenate(([0.0], np.cumsum(np.log(one_minus))))
    logdet = float(log_v.sum())
    v_last = math.exp(log_v[-1])
    x = np.concatenate(([1.0], -phi)) / v_last  # first column of K^{-1}
    y = np.concatenate(([0.0], x[:0:-1]))
    nfft = sp_fft.next_fast_len(2 * n, real=True)
    x_hat, y_hat = sp_fft.rfft(x, nfft), sp_fft.rfft(y, nfft)
    # L(u)^T z = reverse(L(u) reverse(z))
    zr = z[::-1]
    lxt = _conv(x_hat, zr, n, nfft)[::-1]
    lyt = _conv(y_hat, zr, n, nfft)[::-1]
    alpha = (_conv(x_hat, lxt, n, nfft) - _conv(y_hat, lyt, n, nfft)) / x[0]
    quad = float(z @ alpha)
    loglik = -0.5 * (quad + logdet + n * math.log(2.0 * math.pi))
    if not gradient:
        return loglik, None
    j = np.arange(n, dtype=np.float64)
    lag_weight = n - j  # (n - h) at lag h

    def corr(u_hat, v_hat):  # sum_j u_j v_{j+h}, h = 0..n-1
        return sp_fft.irfft(np.conj(u_hat) * v_hat, nfft)[:n]

    def diag_sums(u, u_hat):  # sum_j (n - h - j) u_j u_{j+h}
        return lag_weight * corr(u_hat, u_hat) - corr(sp_fft.rfft(j * u, nfft), u_hat)

    c = (diag_sums(x, x_hat) - diag_sums(y, y_hat)) / x[0]
    a_hat = sp_fft.rfft(alpha, nfft)
    acorr = corr(a_hat, a_hat)
    grad = acorr - c  # 0.5 * w_h with w_h = 2 for h > 0
    grad[0] *= 0.5
    return loglik, grad


_INDEX: dict = {}  # the |s - t| lag index of the last dense evaluation, by (n, device)


def dense_log_likelihood_terms(z, r, gradient, device):
    """:func:`toeplitz_log_likelihood_terms`'s numbers by a dense Cholesky factorisation on ``device``."""
    import torch

    from roughgp.common.device import check_memory, gaussian_log_density

    n = z.size
    key = (n, str(device))
    if key not in _INDEX:
        # the index, K, its factor and the backward pass's temporaries: about 6 n x n arrays
        check_memory(6 * 8 * n * n, device, f"the dense likelihood of a {n}-point profile")
        _INDEX.clear()
        i = torch.arange(n, device=device)
        _INDEX[key] = (i[None, :] - i[:, None]).abs()
    index = _INDEX[key]
    r_t = torch.as_tensor(r, device=device).requires_grad_(gradient)
    z_t = torch.as_tensor(z, device=device)
    with torch.set_grad_enabled(gradient):
        loglik = gaussian_log_density(r_t[index], z_t)
    if not gradient:
        return float(loglik), None
    (grad,) = torch.autograd.grad(loglik, r_t)
    return float(loglik.detach()), grad.cpu().numpy()


def toeplitz_log_likelihood(z, acvf_values, *, gradient=False, device=None):
    r"""Exact log-likelihood of a zero-mean profile under a stationary Gaussian process, and
    optionally its gradient with respect to the ACVF values, in :math:`O(n^2)`.

    The covariance is the symmetric Toeplitz matrix :math:`K_{st} = r_{|s-t|}` with first
    column ``acvf_values[:n]`` (include any noise variance in ``acvf_values[0]``). Method:
    module docstring (Levinson-Durbin plus Gohberg-Semencul).

    Args:
        z: profile of length n >= 1 (finite), zero mean.
        acvf_values: the ACVF at lags 0, 1, ..., at least n values; K must be positive
            definite.
        gradient: also return ``g`` of shape (n,) with :math:`g_h = \partial\log p /
            \partial r_h` (a change of :math:`r_h` changes both off-diagonals :math:`\pm h`).
        device: None (the :math:`O(n^2)` recursion on the CPU) or a torch device such as
            ``"cuda"``: the dense route there (module docstring), the same numbers.

    Returns:
        the log-likelihood (float), or ``(loglik, g)`` with ``gradient=True``.
    """
    z = np.asarray(z, dtype=np.float64)
    if z.ndim != 1 or z.size < 1:
        raise ValueError(f"z must be a profile of shape (n,) with n >= 1, got shape {z.shape}")
    check_finite("z", z)
    r = np.asarray(acvf_values, dtype=np.float64)
    if r.ndim != 1 or r.size < z.size:
        raise ValueError(f"acvf_values must have shape (m,) with m >= len(z) = {z.size}, "
                         f"got shape {r.shape}")
    check_finite("acvf_values", r)
    device = resolve_device(device)
    try:
        if device is None:
            loglik, grad = toeplitz_log_likelihood_terms(z, r[:z.size], gradient)
        else:
            loglik, grad = dense_log_likelihood_terms(z, r[:z.size], gradient, device)
    except np.linalg.LinAlgError:
        raise ValueError("acvf_values must be positive definite: its Toeplitz matrix of "
                         f"size {z.size} is singular or indefinite") from None
    return (loglik, grad) if gradient else loglik
