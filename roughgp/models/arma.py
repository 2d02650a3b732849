r"""ARMA processes, linear processes and sampled Gaussian processes (paper section 2.3).

Sign convention of the paper, eq 12 (ARMA(p, q)), with white noise :math:`\Delta B_x` of
variance ``sigma2``:

.. math::
    G_x = \sum_{i=1}^{p} a_i G_{x-i} + \sum_{j=1}^{q} b_j \Delta B_{x-j} + \Delta B_x ,

so ``ar = [a_1, ..., a_p]`` and ``ma = [b_1, ..., b_q]`` give the AR polynomial
:math:`\phi(z) = 1 - \sum_i a_i z^i` and the MA polynomial :math:`\theta(z) = 1 + \sum_j b_j z^j`
(the convention of Brockwell & Davis; Box & Jenkins write :math:`\theta` with minus signs).
The process is stationary and causal when every root of :math:`\phi` lies outside the unit
circle; it then is the causal linear process of eq 14,
:math:`G_x = \sum_{k\ge0} \tilde\beta_k \Delta B_{x-k}`, a special case of eq 13, whose
weights (the psi-weights) solve :math:`\phi(z) \sum_k \tilde\beta_k z^k = \theta(z)`.
A Gaussian process is the continuous analogue, a continuous moving average of white noise
(eq 16) with ACVF eq 17; sampling a continuous-time ARMA (CARMA) Gaussian process on a grid
gives an ARMA process, which :func:`ou_to_ar1` and :func:`matern32_to_arma21` make exact.

References: P. J. Brockwell & R. A. Davis, *Time Series: Theory and Methods*, 2nd ed.,
Springer 1991 (``brockwell1991``: §3.1-3.3 linear processes and ARMA, §5.2 Durbin-Levinson,
§8.1 Yule-Walker);
P. J. Brockwell, *Continuous-time ARMA processes*, Handbook of Statistics 19, 2001
(``brockwell2001``); G. E. P. Box & G. M. Jenkins, *Time Series Analysis: Forecasting and
Control*, 1976 (``box1976``).
"""

from __future__ import annotations

import math

import numpy as np
from scipy.signal import lfilter

from roughgp.common.checks import as_generator as _rng
from roughgp.common.checks import check_integer as _int
from roughgp.common.checks import check_size
from roughgp.gp.toeplitz import toeplitz_log_likelihood

__all__ = [
    "arma_acvf", "linear_process_weights", "acvf_from_weights", "simulate_arma",
    "gp_log_likelihood", "arma_log_likelihood", "yule_walker",
    "ou_to_ar1", "ar1_to_ou", "matern32_to_arma21",
]

BURN_IN_TOL = 1e-12
"""Default burn-in of :func:`simulate_arma`: the start-up transient's standard deviation is
below this fraction of the process standard deviation."""

_MAX_BURN_IN = 2**24


# ---------------------------------------------------------------------------- checks

def _float_array(name, value):
    try:
        return np.asarray(value, dtype=np.float64)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be numeric, got {value!r}") from None


def _positive(name, value):
    arr = _float_array(name, value)
    if arr.ndim != 0 or not (np.isfinite(arr) and arr > 0):
        raise ValueError(f"{name} must be a finite scalar > 0 (allowed range: (0, inf)), "
                         f"got {value!r}")
    return float(arr)


def _vector(name, value, min_size=0):
    arr = np.atleast_1d(_float_array(name, value))
    if arr.ndim != 1 or arr.size < min_size:
        raise ValueError(f"{name} must be a 1-D sequence of >= {min_size} numbers, "
                         f"got shape {arr.shape}")
    if not np.all(np.isfinite(arr)):
        raise ValueError(f"{name} must be finite (no NaN or inf), got {arr.tolist()!r}")
    return arr


def _step_down(ar):
    """Reflection coefficients kappa_1..kappa_p of phi and its coefficients of orders 0..p.

    Durbin-Levinson run backwards from ``phi_p = ar`` (Brockwell & Davis 1991, §5.2);
    the AR part is stationary (causal) iff every |kappa_m| < 1 (the Schur-Cohn test), so no
    tolerance on computed roots is needed. Returns ``None`` when it is not.
    """
    phis, kappas = [ar], []
    for _ in range(ar.size):
        phi = phis[-1]
        kappa = phi[-1]
        if not abs(kappa) < 1.0:
            return None
        kappas.append(kappa)
        phis.append((phi[:-1] + kappa * phi[-2::-1]) / (1.0 - kappa * kappa))
    return np.array(kappas[::-1]), phis[::-1]


def _arma(ar, ma):
    """Checked float64 ``(ar, ma)``; raises unless the AR part is stationary (causal)."""
    ar, ma = _vector("ar", ar), _vector("ma", ma)
    if _step_down(ar) is None:
        roots = np.roots(np.r_[-ar[::-1], 1.0])  # phi(z), highest power first
        raise ValueError(
            f"ar must give a stationary AR part: every root of phi(z) = 1 - sum_i a_i z^i "
            f"must lie outside the unit circle (|z| > 1; for AR(1): -1 < a_1 < 1), got "
            f"ar={ar.tolist()} with a root of modulus {np.abs(roots).min():.6g}")
    return ar, ma


# ------------------------------------------------------------- ACVF and eq 13-14

def _psi(ar, ma, n):
    """The first ``n`` psi-weights: the impulse response of theta(B) / phi(B)."""
    impulse = np.zeros(n)
    impulse[0] = 1.0
    return lfilter(np.r_[1.0, ma], np.r_[1.0, -ar], impulse)


def linear_process_weights(ar, ma, n):
    r"""Weights :math:`\tilde\beta_0 = 1, \tilde\beta_1, \dots, \tilde\beta_{n-1}` of eq 14.

    The causal MA(:math:`\infty`) representation of a stationary ARMA(p, q) (eq 12),
    :math:`\tilde\beta_k = b_k + \sum_{i=1}^{\min(k,p)} a_i \tilde\beta_{k-i}` with
    :math:`b_0 = 1, b_k = 0` for k > q (Brockwell & Davis 1991, §3.1). For a pure MA(q)
    (``ar=[]``) these are the finite weights ``[1, b_1, ..., b_q, 0, ...]`` of eq 13.

    Args:
        ar: AR coefficients ``[a_1, ..., a_p]`` of eq 12 (stationary).
        ma: MA coefficients ``[b_1, ..., b_q]`` of eq 12.
        n: number of weights (>= 1).

    Returns:
        float64 array of shape ``(n,)``.
    """
    ar, ma = _arma(ar, ma)
    return _psi(ar, ma, _int("n", n, 1))


def acvf_from_weights(weights, sigma2, nlags):
    r"""ACVF :math:`r(h) = \sigma^2 \sum_k \beta_k \beta_{k+h}` of the linear process eq 13.

    Lags ``h = 0 .. nlags - 1``; with the truncated weights of
    :func:`linear_process_weights` this approximates :func:`arma_acvf` and converges to it
    as the truncation grows (eq 14).

    Args:
        weights: 1-D weights :math:`\beta_0, \beta_1, \dots` (finitely many).
        sigma2: white-noise variance (> 0).
        nlags: number of lags (>= 1).
    """
    w = _vector("weights", weights, min_size=1)
    sigma2, nlags = _positive("sigma2", sigma2), _int("nlags", nlags, 1)
    out = np.zeros(nlags)
    for h in range(min(nlags, w.size)):
        out[h] = w[: w.size - h] @ w[h:]
    return sigma2 * out


def arma_acvf(ar, ma, sigma2, nlags):
    r"""Exact ACVF of the stationary ARMA(p, q) of eq 12 at lags ``0 .. nlags - 1``.

    No simulation, no truncation. With :math:`X = \phi(B)^{-1} \Delta B` the AR(p) part
    (unit noise variance) and :math:`G = \theta(B) X`,
    :math:`\gamma_G(h) = \sigma^2 \sum_{l=-q}^{q} c_l\, \gamma_X(h - l)` with
    :math:`c_l = \sum_j b_j b_{j+l}` (:math:`b_0 = 1`; Brockwell & Davis 1991, Prop. 3.1.2).
    :math:`\gamma_X(0..p)` follow from the reflection coefficients :math:`\kappa_m` of
    :math:`\phi` (Durbin-Levinson backwards, then forwards:
    :math:`\gamma_X(0) = 1 / \prod_m (1 - \kappa_m^2)`), the rest from
    :math:`\gamma_X(k) = \sum_i a_i \gamma_X(k - i)`. This is markedly more accurate than
    solving the linear system of Brockwell & Davis §3.3 (method 2) when roots of
    :math:`\phi` cluster near the unit circle.

    Args:
        ar: AR coefficients ``[a_1, ..., a_p]``; every root of :math:`\phi` must lie
            outside the unit circle, else ``ValueError``.
        ma: MA coefficients ``[b_1, ..., b_q]``.
        sigma2: white-noise variance (> 0).
        nlags: number of lags (>= 1).

    Returns:
        float64 array of shape ``(nlags,)``.
    """
    ar, ma = _arma(ar, ma)
    sigma2, nlags = _positive("sigma2", sigma2), _int("nlags", nlags, 1)
    kappas, phis = _step_down(ar)
    p, q = ar.size, ma.size
    gamma = np.empty(max(nlags + q, p + 1))
    gamma[0] = v = 1.0 / np.prod(1.0 - kappas * kappas)
    for m in range(1, p + 1):  # Durbin-Levinson forwards, solved for gamma(m)
        gamma[m] = kappas[m - 1] * v + phis[m - 1] @ gamma[m - 1 : 0 : -1]
        v *= 1.0 - kappas[m - 1] ** 2
    for k in range(p + 1, gamma.size):
        gamma[k] = ar @ gamma[k - 1 :: -1][:p] if p else 0.0
    theta = np.r_[1.0, ma]
    c = np.correlate(theta, theta, "full")  # c_l, l = -q..q
    lags = np.abs(np.arange(nlags)[:, None] - np.arange(-q, q + 1)[None, :])
    return sigma2 * (gamma[lags] @ c)


# ------------------------------------------------------------------- simulation

def _burn_in(ar, ma, tol=BURN_IN_TOL):
    """Smallest B with sum_{k >= B} psi_k^2 <= tol^2 sum_k psi_k^2 (weights in a window >= 2B)."""
    n = 64
    while n <= _MAX_BURN_IN:
        tail = np.cumsum(_psi(ar, ma, n)[::-1] ** 2)[::-1]  # tail[k] = sum_{j>=k} psi_j^2
        small = np.flatnonzero(tail <= tol**2 * tail[0])
        if small.size and small[0] <= n // 2:
            return int(small[0])
        n *= 2
    raise ValueError(f"ar={ar.tolist()} decays too slowly for an automatic burn-in "
                     f"(> {_MAX_BURN_IN} steps): pass burn_in explicitly")


def simulate_arma(ar, ma, sigma2, n, *, n_samples=1, burn_in=None, seed=None):
    r"""Draw profiles of the stationary Gaussian ARMA(p, q) of eq 12.

    Gaussian white noise of variance ``sigma2`` is filtered by :math:`\theta(B)/\phi(B)`
    (``scipy.signal.lfilter``, zero initial state) and the first ``burn_in`` values are
    dropped. The zero start leaves out :math:`\sum_{k>t} \tilde\beta_k \Delta B_{t-k}` of
    eq 14 at step t; the default ``burn_in`` is the smallest B whose left-out part has a
    standard deviation below ``BURN_IN_TOL`` (1e-12) of the process standard deviation,
    found from the decay of the weights (B = q + 1 for a pure MA(q)).

    Args:
        ar, ma, sigma2: the ARMA of eq 12 (AR part stationary, ``sigma2 > 0``).
        n: profile length (>= 1).
        n_samples: number of independent profiles (>= 1).
        burn_in: steps dropped at the start (>= 0); ``None`` for the default above.
        seed: int >= 0, ``None`` or ``numpy.random.Generator``; same seed, same array.

    Returns:
        float64 array of shape ``(n_samples, n)``.
    """
    ar, ma = _arma(ar, ma)
    sigma2, n = _positive("sigma2", sigma2), _int("n", n, 1)
    n_samples = _int("n_samples", n_samples, 1)
    burn_in = _burn_in(ar, ma) if burn_in is None else _int("burn_in", burn_in, 0)
    check_size(f"n_samples = {n_samples} profiles of n = {n} points and burn_in = {burn_in}",
               n_samples * (burn_in + n), copies=2)
    noise = math.sqrt(sigma2) * _rng(seed).standard_normal((n_samples, burn_in + n))
    return lfilter(np.r_[1.0, ma], np.r_[1.0, -ar], noise, axis=1)[:, burn_in:]


# ------------------------------------------------- Toeplitz likelihood, Yule-Walker

def _durbin_levinson(acvf_values, order):
    """Yield ``(phi_m, v_m)`` for m = 0..order: the coefficients of the best linear predictor
    of a value from its m predecessors and its error variance (Brockwell & Davis 1991, §5.2)."""
    phi, v = np.zeros(0), acvf_values[0]
    for m in range(order + 1):
        if not v > 0:
            raise ValueError(f"acvf_values must be positive definite: the Toeplitz matrix of "
                             f"lags 0..{m} is singular or indefinite (prediction-error "
                             f"variance {v:.3g})")
        yield phi, v
        if m < order:
            kappa = (acvf_values[m + 1] - phi @ acvf_values[m:0:-1]) / v
            phi, v = np.r_[phi - kappa * phi[::-1], kappa], v * (1.0 - kappa * kappa)


def gp_log_likelihood(z, acvf_values):
    r"""Exact log-likelihood of a zero-mean profile ``z`` under a stationary Gaussian process.

    The covariance is the Toeplitz matrix :math:`K_{st} = r(|s - t|)` with first column
    ``acvf_values[:len(z)]`` (the sampled kernel: R of eq 10). In the innovations form the
    Durbin-Levinson recursion gives the one-step prediction errors :math:`e_t` and their
    variances :math:`v_t`, and :math:`\log p(z) = -\tfrac12 \sum_t (\log 2\pi v_t +
    e_t^2 / v_t)` (Brockwell & Davis 1991, §5.2, §8.6): the exact Gaussian likelihood in
    :math:`O(n^2)`. It is evaluated by :func:`roughgp.gp.toeplitz.toeplitz_log_likelihood`
    (the same recursion, compiled, with the quadratic form by FFT).

    Args:
        z: 1-D profile of length n (finite), zero mean.
        acvf_values: ACVF at lags 0, 1, ... (at least n values).
    """
    z = _vector("z", z, min_size=1)
    r = _vector("acvf_values", acvf_values, min_size=z.size)
    return toeplitz_log_likelihood(z, r)


def arma_log_likelihood(z, ar, ma, sigma2):
    """Exact log-likelihood of ``z`` under the Gaussian ARMA(p, q) of eq 12.

    :func:`gp_log_likelihood` with the Toeplitz covariance of :func:`arma_acvf`: an ARMA is
    the Gaussian process on the grid whose ACVF is the ARMA's (section 2.3).
    """
    z = _vector("z", z, min_size=1)
    return gp_log_likelihood(z, arma_acvf(ar, ma, sigma2, z.size))


def yule_walker(acvf_values, p):
    r"""AR(p) fit by the Yule-Walker equations, solved by Durbin-Levinson.

    The coefficients solve :math:`\sum_j a_j \gamma(|i-j|) = \gamma(i)`, i = 1..p, and
    :math:`\sigma^2 = \gamma(0) - \sum_j a_j \gamma(j)` (Brockwell & Davis 1991, §8.1). From
    the exact ACVF of an AR(p) (:func:`arma_acvf`) this recovers its coefficients; from a
    kernel's ACVF it gives the AR(p) whose ACVF matches the kernel at lags 0..p.

    Args:
        acvf_values: ACVF at lags 0, 1, ..., at least p + 1 values (positive definite).
        p: AR order, 0 <= p <= len(acvf_values) - 1.

    Returns:
        ``(ar, sigma2)``: ``ar`` of shape ``(p,)`` in the sign convention of eq 12.
    """
    r = _vector("acvf_values", acvf_values, min_size=1)
    if isinstance(p, bool) or not isinstance(p, (int, np.integer)) or not 0 <= p < r.size:
        raise ValueError(f"p must be an integer in [0, {r.size - 1}] (len(acvf_values) - 1), "
                         f"got {p!r}")
    for phi, v in _durbin_levinson(r, int(p)):
        pass
    return phi, float(v)


# ----------------------------------------------- sampled continuous-time GPs as ARMA

def ou_to_ar1(variance, lengthscale, spacing):
    r"""The exponential (Ornstein-Uhlenbeck, Matérn-1/2) kernel sampled at ``spacing`` as AR(1).

    :math:`\sigma_k^2 e^{-|t|/\lambda}` at t = k d is exactly the ACVF of an AR(1) with
    :math:`a = e^{-d/\lambda}` and :math:`\sigma^2 = \sigma_k^2 (1 - a^2)`: the sampled
    CAR(1) (Brockwell 2001). In general a sampled CARMA(p, q) is an ARMA(p, p - 1), not an
    ARMA(p, q) (see :func:`matern32_to_arma21`). The converse fails: not every ARMA or AR is
    a sampled CARMA of the same order; an AR(1) with a < 0 is no sampled OU process, since
    :math:`e^{-d/\lambda} > 0` (:func:`ar1_to_ou`).

    Returns:
        ``(ar, ma, sigma2)`` with ``ar = [a]``, ``ma = []``.
    """
    variance, lengthscale = _positive("variance", variance), _positive("lengthscale", lengthscale)
    x = _positive("spacing", spacing) / lengthscale
    return np.array([math.exp(-x)]), np.zeros(0), variance * -math.expm1(-2.0 * x)


def ar1_to_ou(a, sigma2, spacing):
    r"""``(variance, lengthscale)`` of the OU process whose samples at ``spacing`` are AR(1).

    Inverse of :func:`ou_to_ar1`: :math:`\lambda = -d / \log a`,
    :math:`\sigma_k^2 = \sigma^2 / (1 - a^2)`. Only 0 < a < 1 is a sampled OU process:
    :math:`e^{-d/\lambda} > 0`, so an AR(1) with a <= 0 (an alternating ACVF) is not one,
    and a >= 1 is not stationary.
    """
    arr = _float_array("a", a)
    if arr.ndim != 0 or not 0.0 < arr < 1.0:
        raise ValueError(f"a must be in (0, 1) for a sampled OU process (a = exp(-spacing / "
                         f"lengthscale) > 0; a >= 1 is not stationary), got {a!r}")
    a = float(arr)
    sigma2, spacing = _positive("sigma2", sigma2), _positive("spacing", spacing)
    return sigma2 / -math.expm1(2.0 * math.log(a)), -spacing / math.log(a)


def _matern32_filtered(c):
    """MA(1) ACVF ``(c0, c1)`` of phi(B) applied to the unit-variance sampled Matern-3/2."""
    rho = math.exp(-c)
    if c >= 1.0:  # no cancellation; stays finite for large c (then rho -> 0)
        return 1.0 - rho**4 - 4.0 * c * rho**2, rho * (c * (1.0 + rho**2) - (1.0 - rho**2))
    k = np.arange(1, 15)  # series of sinh x - x and x cosh x - sinh x, all terms positive
    inv_fact = 1.0 / np.array([math.factorial(2 * j + 1) for j in k])
    sinh_tail = np.sum((2.0 * c) ** (2 * k + 1) * inv_fact)
    cosh_tail = np.sum(2 * k * c ** (2 * k + 1) * inv_fact)
    return 2.0 * rho * rho * sinh_tail, 2.0 * rho * rho * cosh_tail


def matern32_to_arma21(variance, lengthscale, spacing):
    r"""The Matérn-3/2 kernel sampled at ``spacing`` as an exact ARMA(2, 1).

    :math:`\sigma_k^2 (1 + c|k|)\rho^{|k|}` with :math:`c = \sqrt3 d/\lambda`,
    :math:`\rho = e^{-c}` is the ACVF of a sampled CAR(2) with a double root, so
    :math:`\phi(z) = (1 - \rho z)^2`: :math:`a_1 = 2\rho, a_2 = -\rho^2`. Filtered by
    :math:`\phi(B)` the samples have an MA(1) ACVF, zero beyond lag 1:
    :math:`c_0 = \sigma_k^2 (1 - \rho^4 - 4c\rho^2) = 2\sigma_k^2 \rho^2(\sinh 2c - 2c)`,
    :math:`c_1 = \sigma_k^2 \rho(c(1+\rho^2)-1+\rho^2) = 2\sigma_k^2 \rho^2(c\cosh c - \sinh c)`
    (for c < 1 the sinh forms, summed as series, avoid cancellation). Spectral
    factorisation :math:`\sigma^2(1 + b^2) = c_0, \sigma^2 b = c_1` with the invertible root
    ``|b| < 1`` gives the MA part. A sampled CAR(2) is ARMA(2, 1), not AR(2) (Brockwell 2001).

    Returns:
        ``(ar, ma, sigma2)`` with ``ar = [2 rho, -rho^2]``, ``ma = [b]``.
    """
    variance, lengthscale = _positive("variance", variance), _positive("lengthscale", lengthscale)
    c = math.sqrt(3.0) * _positive("spacing", spacing) / lengthscale
    rho = math.exp(-c)
    c0, c1 = (variance * float(x) for x in _matern32_filtered(c))
    t = c1 / c0  # b / (1 + b^2), in [0, 1/2)
    b = 2.0 * t / (1.0 + math.sqrt(1.0 - 4.0 * t * t))
    return np.array([2.0 * rho, -rho * rho]), np.array([b]), c0 / (1.0 + b * b)
