r"""Two-dimensional autoregressions on a grid: the AR part of eq 12 with a 2-D support.

A 2-D AR model of a surface on the integer grid :math:`\boldsymbol s = (s_x, s_y)` is

.. math::
    G_{\boldsymbol s} = \sum_{\boldsymbol k \in K} a_{\boldsymbol k}\,
    G_{\boldsymbol s - \boldsymbol k} + \Delta B_{\boldsymbol s},

with white noise :math:`\Delta B` of variance ``sigma2`` and a finite support :math:`K`
(:func:`ar_support`): the *quarter plane* :math:`\{0..p\}^2 \setminus \{0\}` or the
*non-symmetric half plane* (``half``: :math:`k_y = 0, 1 \le k_x \le p` and
:math:`1 \le k_y \le p, |k_x| \le p`), the two causal orderings of a 2-D recursion. Its PSD
is :math:`\sigma^2 / |1 - \sum_K a_{\boldsymbol k} e^{-2\pi i \boldsymbol f\cdot
\boldsymbol k}|^2` (the 2-D form of the 1-D ARMA PSD, eq 14's linear process), a ratio of
trigonometric polynomials. The 1-D exponential is an AR(1)
(:func:`roughgp.models.arma.ou_to_ar1`); eq 18's PSD
(:func:`roughgp.gp.acvf.rotated_exponential_psd`, a power 3/2 of a quadratic form) has no such
closed form on the lattice, and how close a finite support gets is what
:mod:`roughgp.experiments.long_correlation` measures.

* :func:`ar_support`: the lags of the support of order ``p``;
* :func:`yule_walker_2d`: the coefficients from an ACVF by the 2-D Yule-Walker (normal)
  equations :math:`\sum_{\boldsymbol j\in K} a_{\boldsymbol j}\, r(\boldsymbol k -
  \boldsymbol j) = r(\boldsymbol k)`, :math:`\boldsymbol k \in K`, the minimum-variance
  linear predictor on the support (also what least squares on a long record converges to);
* :func:`ar_acvf_2d`: the model's ACVF on a torus, from its PSD by an inverse FFT (exact up to
  periodisation at the torus size).

Reference: D. E. Dudgeon & R. M. Mersereau, *Multidimensional Digital Signal Processing*,
Prentice-Hall 1984, ch. 6 (2-D linear prediction, quarter- and half-plane supports).
"""

from __future__ import annotations

import numpy as np

from roughgp.common.checks import check_integer as _int

__all__ = ["SUPPORTS", "ar_acvf_2d", "ar_support", "yule_walker_2d"]

SUPPORTS = ("quarter", "half")
"""The supports of :func:`ar_support`: quarter plane, non-symmetric half plane."""

_MAX_COEFFICIENTS = 5000        # the normal equations are dense: 5000^2 doubles = 200 MB


def ar_support(order: int, kind: str = "half") -> np.ndarray:
    """The lags ``(k_x, k_y)`` of a 2-D AR support of ``order`` p, shape (m, 2), int.

    ``kind="quarter"``: :math:`\\{0..p\\}^2` without the origin, m = (p + 1)^2 - 1;
    ``kind="half"``: the non-symmetric half plane, m = p + p (2p + 1).
    """
    p = _int("order", order, 1)
    if kind == "quarter":
        lags = [(kx, ky) for ky in range(p + 1) for kx in range(p + 1) if (kx, ky) != (0, 0)]
    elif kind == "half":
        lags = [(kx, 0) for kx in range(1, p + 1)]
        lags += [(kx, ky) for ky in range(1, p + 1) for kx in range(-p, p + 1)]
    else:
        raise ValueError(f"kind must be one of {SUPPORTS}, got {kind!r}")
    if len(lags) > _MAX_COEFFICIENTS:
        raise ValueError(f"order {p} gives {len(lags)} coefficients, more than "
                         f"{_MAX_COEFFICIENTS} (dense normal equations); use a smaller order")
    return np.array(lags, dtype=int)


def _lag_values(acvf, lags):
    values = np.asarray(acvf(np.asarray(lags, dtype=np.float64)), dtype=np.float64)
    if values.shape != lags.shape[:-1] or not np.all(np.isfinite(values)):
        raise ValueError(f"acvf must return finite values of shape {lags.shape[:-1]} for lags "
                         f"of shape {lags.shape}, got shape {values.shape}")
    return values


def yule_walker_2d(acvf, support) -> tuple[np.ndarray, float]:
    """2-D AR coefficients on ``support`` from an ACVF by the Yule-Walker equations.

    Args:
        acvf: a function of lags of shape (..., 2), components ``(tau_x, tau_y)`` in grid
            units (a kernel's ``acvf``, e.g. eq 18's).
        support: lags ``(k_x, k_y)`` of shape (m, 2) (:func:`ar_support`).

    Returns:
        ``(coefficients, sigma2)``: :math:`a_{\\boldsymbol k}` in the order of ``support`` and
        the innovation variance :math:`r(0) - \\sum a_{\\boldsymbol k} r(\\boldsymbol k)`.
    """
    support = np.asarray(support)
    if support.ndim != 2 or support.shape[1] != 2 or support.shape[0] < 1:
        raise ValueError(f"support must have shape (m >= 1, 2), got {support.shape}")
    if len(support) > _MAX_COEFFICIENTS:
        raise ValueError(f"support has {len(support)} lags, more than {_MAX_COEFFICIENTS}")
    differences = support[:, None, :] - support[None, :, :]
    matrix = _lag_values(acvf, differences)
    rhs = _lag_values(acvf, support)
    r0 = float(_lag_values(acvf, np.zeros((1, 2)))[0])
    coefficients = np.linalg.solve(matrix, rhs)
    sigma2 = r0 - float(coefficients @ rhs)
    if not sigma2 > 0:
        raise ValueError(f"the normal equations give a non-positive innovation variance "
                         f"{sigma2:.3g}: the acvf is not positive definite on this support")
    return coefficients, sigma2


def ar_acvf_2d(coefficients, support, sigma2: float, size: int) -> np.ndarray:
    """The ACVF of the 2-D AR model on a ``size`` x ``size`` torus, indexed ``[k_y, k_x]``
    (negative lags wrap to the end), from its PSD by an inverse FFT.

    It is the model's ACVF periodised with period ``size``: exact to rounding at the lags
    where the ACVF has decayed within half the torus.
    """
    n = _int("size", size, 2)
    support = np.asarray(support)
    coefficients = np.asarray(coefficients, dtype=np.float64)
    if coefficients.shape != support.shape[:1]:
        raise ValueError(f"coefficients must have shape {support.shape[:1]}, got "
                         f"{coefficients.shape}")
    if np.abs(support).max() >= n // 2:
        raise ValueError(f"size must exceed twice the support's reach, got {n}")
    polynomial = np.zeros((n, n))
    np.add.at(polynomial, (support[:, 1] % n, support[:, 0] % n), -coefficients)
    polynomial[0, 0] += 1.0
    transfer = np.abs(np.fft.rfft2(polynomial)) ** 2
    if transfer.min() <= 0:
        raise ValueError("the AR polynomial vanishes on the torus' frequencies: no PSD")
    return np.fft.irfft2(float(sigma2) / transfer, s=(n, n))
