r"""Autocovariance functions (ACVFs) and their power spectral densities (PSDs).

Plain functions of lags, the bottom of the library. Every function takes ``lags`` as an
array of shape ``(..., D)`` -- the last axis holds the ``D`` components of the lag
:math:`\boldsymbol\tau = \boldsymbol x' - \boldsymbol x` (for a 2-D surface: ``(tau_x, tau_y)``)
-- and returns an array of shape ``lags.shape[:-1]``. A profile's lags therefore carry a
trailing axis of length 1: ``lags[:, None]``.

The functions work on NumPy arrays and on torch tensors alike (the GPyTorch kernels of
:mod:`roughgp.gp.kernels` call them with tensors, so gradients flow through one formula).

PSDs follow the paper's Fourier convention, eq 5:

.. math::
    S(\boldsymbol f) = \int_{\mathbb R^D} r(\boldsymbol\tau)\,
        e^{-i 2\pi \boldsymbol f^\top \boldsymbol\tau}\, d\boldsymbol\tau, \qquad
    r(\boldsymbol\tau) = \int_{\mathbb R^D} S(\boldsymbol f)\,
        e^{i 2\pi \boldsymbol f^\top \boldsymbol\tau}\, d\boldsymbol f,

with frequencies ``f`` in cycles per unit length (the unit of the lags) and the same
``(..., D)`` layout as the lags.
"""

from __future__ import annotations

import math
import sys
from typing import Callable

import numpy as np

from roughgp.common.checks import check_finite, check_lags, check_positive, check_shape
from roughgp.common.checks import is_tensor as _is_tensor

__all__ = [
    "pairwise_lags",
    "rotate",
    "rotated_exponential",
    "rotated_exponential_psd",
    "rotated_matern",
    "spectral_mixture",
    "spectral_mixture_psd",
    "additive",
    "matern",
    "matern_psd",
    "rectangular",
    "rectangular_psd",
    "MATERN_NUS",
]

MATERN_NUS = (0.5, 1.5, 2.5, math.inf)
"""Smoothness values of the Matérn family with closed forms (inf: squared exponential)."""


def _xp(x):
    """The array namespace of ``x``: ``torch`` for tensors, else ``numpy``."""
    return sys.modules["torch"] if _is_tensor(x) else np


def _like(value, ref):
    """``value`` as an array of the same kind (and, for torch, dtype/device) as ``ref``."""
    if _is_tensor(ref):
        return sys.modules["torch"].as_tensor(value, dtype=ref.dtype, device=ref.device)
    if _is_tensor(value):
        value = value.detach().cpu().numpy()
    return np.asarray(value, dtype=np.result_type(ref, np.float64))


def _as_lags(lags):
    if _is_tensor(lags):
        return lags
    return np.asarray(lags, dtype=np.float64)


def _safe_sqrt(q):
    """sqrt for q >= 0 whose gradient is 0 (not NaN) at q = 0."""
    xp = _xp(q)
    positive = q > 0
    return xp.where(positive, xp.sqrt(xp.where(positive, q, 1.0)), 0.0 * q)


def pairwise_lags(x1, x2=None):
    """Lags ``x2[j] - x1[i]`` between two point sets of shape (n, D) and (m, D): shape (n, m, D).

    With the lags ``tau = x' - x`` of eq 3, ``covariance = acvf(pairwise_lags(x, x))`` is the
    matrix ``R`` of eq 10.
    """
    x1 = _as_lags(x1)
    x2 = x1 if x2 is None else _like(x2, x1)
    if x1.ndim != 2 or x2.ndim != 2 or x1.shape[1] != x2.shape[1]:
        raise ValueError(f"x1 and x2 must have shapes (n, D) and (m, D) with the same D, "
                         f"got {tuple(x1.shape)} and {tuple(x2.shape)}")
    return x2[None, :, :] - x1[:, None, :]


def rotate(lags, angle):
    r"""Apply the inverse rotation :math:`T_\phi` of eq 18: ``tau' = T_phi tau``.

    ``T_phi = [[cos phi, sin phi], [-sin phi, cos phi]]`` turns the direction at angle
    ``phi`` (counter-clockwise from the x-axis) onto the first axis, so a long first
    lengthscale makes the correlation long along that direction.
    """
    xp = _xp(lags)
    angle = _like(angle, lags)
    c, s = xp.cos(angle), xp.sin(angle)
    tx, ty = lags[..., 0], lags[..., 1]
    return xp.stack([c * tx + s * ty, -s * tx + c * ty], axis=-1)


def _check_rotated(lags, variance, lengthscales, angle, name="lags"):
    check_lags(name, lags, 2)
    check_positive("variance", variance)
    check_shape("variance", variance, ())
    check_shape("lengthscales", lengthscales, (2,))
    check_positive("lengthscales", lengthscales)
    check_shape("angle", angle, ())
    check_finite("angle", angle)


def rotated_exponential(lags, variance, lengthscales, angle):
    r"""Rotated anisotropic exponential ACVF, eq 18.

    .. math::
        r_E(\boldsymbol\tau;\phi) = \sigma_k^2 \exp\!\left(-\sqrt{\boldsymbol\tau'^\top
        \boldsymbol\Lambda^{-2}\boldsymbol\tau'}\right), \quad
        \boldsymbol\tau' = \boldsymbol T_\phi \boldsymbol\tau,
        \quad \boldsymbol\Lambda = \operatorname{diag}(\lambda_a, \lambda_b).

    Args:
        lags: shape (..., 2), components ``(tau_x, tau_y)``.
        variance: :math:`\sigma_k^2 > 0`.
        lengthscales: ``(lambda_a, lambda_b)``, both > 0. With ``lambda_a > lambda_b`` the
            grooves run along the direction at ``angle`` from the x-axis.
        angle: :math:`\phi` in radians, counter-clockwise from the x-axis.

    Its PSD is :func:`rotated_exponential_psd`.
    """
    lags = _as_lags(lags)
    _check_rotated(lags, variance, lengthscales, angle)
    xp = _xp(lags)
    lengthscales = _like(lengthscales, lags)
    scaled = rotate(lags, angle) / lengthscales
    return _like(variance, lags) * xp.exp(-_safe_sqrt((scaled * scaled).sum(-1)))


def rotated_exponential_psd(freqs, variance, lengthscales, angle):
    r"""Closed-form PSD of eq 18 (Fourier convention of eq 5).

    .. math::
        S_E(\boldsymbol f) = \frac{2\pi\,\sigma_k^2\,\lambda_a\lambda_b}
        {\left(1 + 4\pi^2\,\lVert \boldsymbol\Lambda \boldsymbol T_\phi \boldsymbol f
        \rVert^2\right)^{3/2}}.

    The isotropic 2-D exponential has the transform :math:`2\pi/(1+4\pi^2|f|^2)^{3/2}`;
    the linear map :math:`\boldsymbol\tau \mapsto \boldsymbol\Lambda^{-1}\boldsymbol T_\phi
    \boldsymbol\tau` scales it by :math:`\det\boldsymbol\Lambda` and maps the frequency to
    :math:`\boldsymbol\Lambda \boldsymbol T_\phi \boldsymbol f`.
    """
    freqs = _as_lags(freqs)
    _check_rotated(freqs, variance, lengthscales, angle, name="freqs")
    lengthscales = _like(lengthscales, freqs)
    scaled = rotate(freqs, angle) * lengthscales
    q = (scaled * scaled).sum(-1)
    return (2 * math.pi * _like(variance, freqs) * lengthscales[0] * lengthscales[1]
            / (1 + 4 * math.pi**2 * q) ** 1.5)


def _check_mixture(lags, weights, means, variances, name="lags"):
    shapes = {k: tuple(np.shape(v.detach() if _is_tensor(v) else v))
              for k, v in (("weights", weights), ("means", means), ("variances", variances))}
    ok = (len(shapes["means"]) == 2 and shapes["variances"] == shapes["means"]
          and shapes["weights"] == shapes["means"][:1])
    if not ok:
        raise ValueError(f"weights, means and variances must have shapes (Q,), (Q, D) and "
                         f"(Q, D) with the same Q and D, got weights {shapes['weights']}, "
                         f"means {shapes['means']}, variances {shapes['variances']}")
    check_positive("weights", weights)
    check_finite("means", means)
    check_positive("variances", variances)
    q, d = shapes["means"]
    check_lags(name, lags, d)
    return q


def spectral_mixture(lags, weights, means, variances):
    r"""Spectral mixture ACVF, eq 21 (Wilson & Adams 2013).

    .. math::
        r_{SM}(\boldsymbol\tau) = \sum_{q=1}^{Q} w_q \cos(2\pi\boldsymbol\tau^\top
        \boldsymbol\mu_q) \exp(-2\pi^2 \boldsymbol\tau^\top \boldsymbol\Sigma_q
        \boldsymbol\tau), \quad \boldsymbol\Sigma_q = \operatorname{diag}(\text{variances}_q).

    Each component is one plane wave (the cosine of the summed phase
    :math:`2\pi\boldsymbol\tau^\top\boldsymbol\mu_q`) under one Gaussian envelope, and the
    components are summed -- unlike GPyTorch's ``SpectralMixtureKernel``, which for D > 1
    sums components per dimension and then multiplies over dimensions. The two agree for
    D = 1 only.

    Args:
        lags: shape (..., D).
        weights: shape (Q,), > 0: :math:`w_q` (the variance of component q).
        means: shape (Q, D): the frequencies :math:`\boldsymbol\mu_q` (cycles per unit length).
        variances: shape (Q, D), > 0: the diagonals of :math:`\boldsymbol\Sigma_q`
            (cycles^2 per unit length^2).
    """
    lags = _as_lags(lags)
    n_components = _check_mixture(lags, weights, means, variances)
    xp = _xp(lags)
    weights, means, variances = (_like(p, lags) for p in (weights, means, variances))
    total = 0.0 * lags[..., 0]
    for q in range(n_components):  # a loop keeps memory at one lag array, not Q of them
        phase = (lags * means[q]).sum(-1)
        decay = (lags * lags * variances[q]).sum(-1)
        total = total + weights[q] * xp.cos(2 * math.pi * phase) * xp.exp(-2 * math.pi**2 * decay)
    return total


def spectral_mixture_psd(freqs, weights, means, variances):
    r"""PSD of eq 21: a symmetrised Gaussian mixture,

    .. math::
        S_{SM}(\boldsymbol f) = \sum_q \frac{w_q}{2}\left[\mathcal N(\boldsymbol f;
        \boldsymbol\mu_q, \boldsymbol\Sigma_q) + \mathcal N(\boldsymbol f; -\boldsymbol\mu_q,
        \boldsymbol\Sigma_q)\right].
    """
    freqs = _as_lags(freqs)
    n_components = _check_mixture(freqs, weights, means, variances, name="freqs")
    xp = _xp(freqs)
    weights, means, variances = (_like(p, freqs) for p in (weights, means, variances))
    total = 0.0 * freqs[..., 0]
    for q in range(n_components):
        norm = 1.0 / xp.sqrt(xp.prod(2 * math.pi * variances[q]))
        for sign in (1.0, -1.0):
            d = freqs - sign * means[q]
            total = total + 0.5 * weights[q] * norm * xp.exp(-0.5 * (d * d / variances[q]).sum(-1))
    return total


def additive(lags, acvf_x: Callable, acvf_y: Callable):
    r"""Additive ACVF of eq 22: :math:`r(\boldsymbol\tau) = r_x(\tau_x) + r_y(\tau_y)`.

    Args:
        lags: shape (..., 2).
        acvf_x, acvf_y: 1-D ACVFs, each called with lags of shape (..., 1), e.g.
            ``lambda t: spectral_mixture(t, w, mu, v)``.

    The sum does not decay along the axes, so it has no PSD as a function: its spectrum is
    :math:`S_x(f_x)\delta(f_y) + \delta(f_x)S_y(f_y)`, concentrated on the two frequency axes.
    """
    lags = _as_lags(lags)
    check_lags("lags", lags, 2)
    return acvf_x(lags[..., 0:1]) + acvf_y(lags[..., 1:2])


def _check_matern(lags, variance, lengthscale, nu, name="lags"):
    arr = lags.detach() if _is_tensor(lags) else np.asarray(lags)
    if arr.ndim == 0:
        raise ValueError(f"{name} must have shape (..., D), got a scalar")
    check_lags(name, lags, arr.shape[-1])
    check_shape("variance", variance, ())
    check_positive("variance", variance)
    check_shape("lengthscale", lengthscale, ())
    check_positive("lengthscale", lengthscale)
    if nu not in MATERN_NUS:
        raise ValueError(f"nu must be one of {MATERN_NUS}, got {nu!r}")


def matern(lags, variance, lengthscale, nu):
    r"""Isotropic Matérn ACVF with smoothness ``nu`` in {1/2, 3/2, 5/2, inf}.

    With :math:`d = |\boldsymbol\tau| / \lambda`: :math:`\nu = 1/2` is the exponential
    :math:`\sigma^2 e^{-d}` (the 1-D case of eq 18, the Ornstein-Uhlenbeck process),
    :math:`\nu = 3/2` is :math:`\sigma^2(1+\sqrt3 d)e^{-\sqrt3 d}`, :math:`\nu = 5/2` is
    :math:`\sigma^2(1+\sqrt5 d+5d^2/3)e^{-\sqrt5 d}` and :math:`\nu=\infty` the squared
    exponential :math:`\sigma^2 e^{-d^2/2}` (Rasmussen & Williams 2006, eq 4.14-4.17).
    """
    lags = _as_lags(lags)
    _check_matern(lags, variance, lengthscale, nu)
    xp = _xp(lags)
    variance = _like(variance, lags)
    q = (lags * lags).sum(-1) / _like(lengthscale, lags) ** 2
    if nu == math.inf:
        return variance * xp.exp(-0.5 * q)
    d = _safe_sqrt(q)
    if nu == 0.5:
        return variance * xp.exp(-d)
    if nu == 1.5:
        s = math.sqrt(3.0) * d
        return variance * (1 + s) * xp.exp(-s)
    s = math.sqrt(5.0) * d
    return variance * (1 + s + s * s / 3) * xp.exp(-s)


def rotated_matern(lags, variance, lengthscales, angle, nu):
    r"""Eq 18's rotated geometric anisotropy with a Matérn radial profile (beyond the paper).

    :math:`r(\boldsymbol\tau) = \sigma_k^2\, M_\nu(\lVert\boldsymbol\Lambda^{-1}\boldsymbol
    T_\phi\boldsymbol\tau\rVert)` with :math:`M_\nu` the unit Matérn correlation of
    :func:`matern`; ``nu = 0.5`` is eq 18 itself (:func:`rotated_exponential`), whose draws are
    continuous but nowhere differentiable; ``nu = 1.5`` and ``2.5`` give once and twice
    differentiable surfaces with the same lay and lengthscales.
    """
    lags = _as_lags(lags)
    _check_rotated(lags, variance, lengthscales, angle)
    if nu not in MATERN_NUS or nu == math.inf:
        raise ValueError(f"nu must be one of 0.5, 1.5, 2.5, got {nu!r}")
    scaled = rotate(lags, angle) / _like(lengthscales, lags)
    return matern(scaled, variance, 1.0, nu)


def matern_psd(freqs, variance, lengthscale, nu):
    r"""PSD of :func:`matern` in D = ``freqs.shape[-1]`` dimensions (R&W 2006, eq 4.15):

    .. math::
        S(\boldsymbol f) = \sigma^2 \frac{2^D \pi^{D/2}\Gamma(\nu+D/2)(2\nu)^\nu}
        {\Gamma(\nu)\lambda^{2\nu}} \left(\frac{2\nu}{\lambda^2} + 4\pi^2|\boldsymbol f|^2
        \right)^{-(\nu+D/2)},

    and :math:`\sigma^2 (2\pi\lambda^2)^{D/2} e^{-2\pi^2\lambda^2|\boldsymbol f|^2}` for
    :math:`\nu=\infty`.
    """
    freqs = _as_lags(freqs)
    _check_matern(freqs, variance, lengthscale, nu, name="freqs")
    xp = _xp(freqs)
    dim = freqs.shape[-1]
    variance, lengthscale = _like(variance, freqs), _like(lengthscale, freqs)
    f2 = (freqs * freqs).sum(-1)
    if nu == math.inf:
        return variance * (2 * math.pi * lengthscale**2) ** (dim / 2) * xp.exp(
            -2 * math.pi**2 * lengthscale**2 * f2)
    const = (2**dim * math.pi ** (dim / 2) * math.gamma(nu + dim / 2) * (2 * nu) ** nu
             / math.gamma(nu))
    return variance * const / lengthscale ** (2 * nu) * (
        2 * nu / lengthscale**2 + 4 * math.pi**2 * f2) ** (-(nu + dim / 2))


def rectangular(lags, variance, width):
    r"""A function that is *not* a valid ACVF: :math:`\sigma^2\,\mathbb 1(|\tau| \le a)` (1-D).

    Kept as a counter-example (section 2.1): it is symmetric and largest at zero, yet its
    Fourier transform :func:`rectangular_psd` goes negative, so covariance matrices built
    from it are not positive semi-definite and cannot be sampled from.
    """
    lags = _as_lags(lags)
    check_lags("lags", lags, 1)
    check_positive("variance", variance)
    check_positive("width", width)
    xp = _xp(lags)
    inside = xp.abs(lags[..., 0]) <= _like(width, lags)
    return _like(variance, lags) * inside


def rectangular_psd(freqs, variance, width):
    r"""Fourier transform of :func:`rectangular`: :math:`2a\sigma^2\,\mathrm{sinc}(2af)`,
    negative on every other side lobe."""
    freqs = _as_lags(freqs)
    check_lags("freqs", freqs, 1)
    check_positive("variance", variance)
    check_positive("width", width)
    width = float(width)
    return float(variance) * 2 * width * np.sinc(2 * width * np.asarray(freqs)[..., 0])
