r"""Gaussian regression filters, plain and robust (ISO 16610-31 profiles, ISO 16610-71 surfaces).

The Gaussian regression filter of order :math:`p` (Seewig, "Linear and robust Gaussian
regression filters", J. Phys.: Conf. Ser. 13, 2005; ISO 16610-31) fits, at every point
:math:`x_k`, a polynomial of degree :math:`p` to the heights by weighted least squares with
the Gaussian weights :math:`s(x_i - x_k) = \exp(-\pi ((x_i - x_k)/(\gamma \lambda_c))^2)`;
the mean line at :math:`x_k` is the polynomial's value there. On a surface (ISO 16610-71) the
polynomial is in :math:`(x, y)` (1, x, y for order 1; and x², xy, y² for order 2) and the
weight the product of the two axes' Gaussians.

* Order 0 is the Gaussian filter of ISO 16610-21 / -61
  (:func:`roughgp.metrology.filters.gaussian_filter`), its ends corrected to zeroth order.
  Order 2 fits a parabola: it reproduces a quadratic form exactly up to the ends (the
  standard's end-effect correction beyond zeroth order). Its constant :math:`\gamma` keeps
  50 % transmission at the cut-off:
  in the interior the order-2 transmission is :math:`(1 + t)e^{-t}` with
  :math:`t = \pi (\gamma \lambda_c / \lambda)^2`, so :math:`\gamma = \sqrt{t_{1/2}/\pi}`
  with :math:`t_{1/2} = -1 - W_{-1}(-1/(2e))`, :math:`\gamma = 0.7309` (:data:`GAMMA`).
* Robust (ISO 16610-31 / -71): the weights are multiplied by Tukey's biweight of the
  residuals :math:`r = z - w`, :math:`\delta = (1 - (r/c)^2)^2` for :math:`|r| < c` and 0
  beyond, with :math:`c = 4.4\,\mathrm{median}|r|` (about three standard deviations of
  Gaussian residuals), recomputed each iteration from the plain filter's residuals on, until
  the scale :math:`c` or the mean line settles (``tol``). A spike or a deep valley then gets no
  weight and the mean line does not follow it, where the plain Gaussian mean line does.

NaN marks an unmeasured point: it takes no weight (its :math:`\delta` is 0) and stays NaN in
the mean line. A point whose window holds too few points for the polynomial (inside or beside
a large hole) takes the zeroth-order value. Each filter is a few separable FFT convolutions
(the weighted moments of the local coordinates) per iteration and one small solve per point.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from roughgp.common.checks import check_integer, check_positive, height_map
from roughgp.common.convolution import convolve_same
from roughgp.common.grid import normalize
from roughgp.metrology.filters import ALPHA, check_cutoff

__all__ = ["GAMMA", "ROBUST_C", "WEIGHT_FLOOR", "RegressionFilter", "regression_filter",
           "robust_gaussian_filter", "robust_l_filter", "tukey_biweight",
           "regression_transmission"]



def _lambert_w_lower(x: float) -> float:
    """The lower branch :math:`W_{-1}(x)` of Lambert's W for :math:`-1/e < x < 0`: the root
    :math:`w < -1` of :math:`w e^w = x`, by bisection (:math:`w e^w` falls monotonically
    from 0 to :math:`-1/e` on :math:`(-\\infty, -1]`); ``scipy.special.lambertw(x, -1)``
    without importing scipy.special (0.2-0.35 s of every ``roughgp texture``)."""
    if not -1.0 / math.e < x < 0.0:
        raise ValueError(f"x must be in (-1/e, 0), got {x!r}")
    low, high = -2.0, -1.0
    while low * math.exp(low) < x:  # below the root: w e^w > x there
        low *= 2.0
    while True:
        middle = 0.5 * (low + high)
        if middle in (low, high):
            return middle
        if middle * math.exp(middle) > x:
            low = middle
        else:
            high = middle


#: gamma of the Gaussian regression filter, by order: 50 % transmission at the cut-off
#: (order 2: ISO 16610-21's sqrt((-1 - W_{-1}(-1 / (2 e))) / pi)).
GAMMA = {0: ALPHA, 1: ALPHA,
         2: math.sqrt((-1.0 - _lambert_w_lower(-0.5 / math.e)) / math.pi)}
ROBUST_C = 4.4  #: c = ROBUST_C * median(abs(r)) of ISO 16610-31's Tukey biweight
WEIGHT_FLOOR = 1e-7  #: the Gaussian weights are cut where they fall below this


def tukey_biweight(residual, c):
    """Tukey's biweight :math:`(1 - (r/c)^2)^2` for :math:`|r| < c`, 0 beyond (NaN -> 0)."""
    u = np.asarray(residual, dtype=np.float64) / c
    return np.where(np.abs(u) < 1, (1 - u * u) ** 2, 0.0)


def regression_transmission(wavelength, cutoff, order=2):
    """Amplitude transmission of the order-0 (:math:`e^{-t}`) or order-2 (:math:`(1+t)e^{-t}`)
    Gaussian regression mean line in the interior, :math:`t = \\pi(\\gamma\\lambda_c/\\lambda)^2`."""
    t = math.pi * (GAMMA[order] * np.asarray(cutoff) / np.asarray(wavelength)) ** 2
    return np.exp(-t) * (1 + t) if order == 2 else np.exp(-t)


@dataclass(frozen=True)
class RegressionFilter:
    """What :func:`regression_filter` returns.

    Attributes:
        mean: the mean line / surface (NaN where ``z`` is NaN).
        weights: the robust weights :math:`\\delta` of the last iteration (1 without robustness,
            0 at NaN).
        c: the biweight's constant of the last iteration (None without robustness).
        iterations: robust iterations run (0 without robustness); converged: whether the mean
            line settled within ``tol * c``.
    """

    mean: np.ndarray
    weights: np.ndarray
    c: float | None
    iterations: int
    converged: bool


def _powers(order, ndim):
    """The exponents of the polynomial's terms: (a,) for a profile, (ax, ay) for a surface."""
    if ndim == 1:
        return [(a,) for a in range(order + 1)]
    return [(ax, ay) for total in range(order + 1) for ay in range(total + 1)
            for ax in (total - ay,)]


def _axis_kernels(cutoff, spacing, order, max_power):
    """Per axis: ``{a: s(u) (-u)^a}`` sampled at the grid's lags (u in units of gamma * cutoff)."""
    gamma = GAMMA[order]
    reach = math.sqrt(-math.log(WEIGHT_FLOOR) / math.pi)  # s(u) < floor beyond
    kernels = []
    for d in spacing:
        half = int(math.floor(reach * gamma * cutoff / d))
        u = np.arange(-half, half + 1) * d / (gamma * cutoff)
        s = np.exp(-math.pi * u * u)
        kernels.append({a: s * (-u) ** a for a in range(max_power + 1)})
    return kernels


def _moments(field, kernels, power):
    """``sum_i s(x_i - x_k) (x_i - x_k)^power f_i`` at every ``k``, by separable convolutions."""
    out = field
    # kernels are in array order (y, x); a surface's powers are (ax, ay)
    for axis, (k, a) in enumerate(zip(kernels, power[::-1])):
        out = convolve_same(out, k[a], axis)
    return out


def _fit(z0, delta, kernels, order):
    """The weighted local polynomial's value at every point (zeroth order where the normal
    equations are near singular), the weights ``delta`` times the Gaussian."""
    ndim = z0.ndim
    terms = _powers(order, ndim)
    cache = {}

    def moment(power):  # of the weights alone (the Gram matrix), each power once
        if power not in cache:
            cache[power] = _moments(delta, kernels, power)
        return cache[power]

    weighted = delta * z0
    m00 = moment(terms[0])
    with np.errstate(invalid="ignore", divide="ignore"):
        mean0 = _moments(weighted, kernels, terms[0]) / m00
    if order == 0:
        return mean0, m00
    n = len(terms)
    gram = np.empty(z0.shape + (n, n))
    rhs = np.empty(z0.shape + (n,))
    for i, p in enumerate(terms):
        rhs[..., i] = _moments(weighted, kernels, p)
        for j, q in enumerate(terms[i:], start=i):
            gram[..., i, j] = gram[..., j, i] = moment(tuple(a + b for a, b in zip(p, q)))
    scale = np.maximum(m00, np.finfo(float).tiny)[..., None, None]
    gram = gram / scale
    rhs = rhs / scale[..., 0]
    # near-singular windows (few points, a line of points): the zeroth-order value instead
    # Hadamard's ratio det / prod(diag) in (0, 1]: near 0 for a near-singular window
    good = np.linalg.det(gram) > 1e-10 * np.prod(np.diagonal(gram, axis1=-2, axis2=-1), axis=-1)
    out = mean0.copy()
    out[good] = np.linalg.solve(gram[good], rhs[good][..., None])[..., 0, 0]
    return out, m00


def regression_filter(z, spacing, cutoff, *, order=2, robust=True, tol=1e-3,
                      max_iter=50) -> RegressionFilter:
    """The (robust) Gaussian regression mean line of a profile (ISO 16610-31) or mean surface
    (ISO 16610-71) (module docstring).

    Args:
        z: a profile ``z[ix]`` or surface ``z[iy, ix]``; NaN marks unmeasured points.
        spacing: scalar or ``(dy, dx)``, > 0.
        cutoff: the cut-off wavelength / nesting index, >= 2 spacings.
        order: the local polynomial's degree, 0, 1 or 2 (2: the standard's choice for the
            robust filter, with the end correction that comes with it).
        robust: Tukey-biweight iterations (True) or the plain regression filter (False).
        tol: the iterations stop when the mean line moves by less than ``tol * c`` or ``c``
            changes by less than ``tol`` of itself (on a real map a few points at a border
            can keep the mean line creeping after the scale has settled); > 0.
        max_iter: at most this many robust iterations, >= 1.
    """
    arr = height_map(z)
    _, sp = normalize(arr.shape, spacing)
    cutoff = check_cutoff("cutoff", cutoff, sp)
    if order not in (0, 1, 2):
        raise ValueError(f"order must be 0, 1 or 2 (allowed: 0, 1, 2), got {order!r}")
    check_positive("tol", tol)
    max_iter = check_integer("max_iter", max_iter, 1)
    measured = np.isfinite(arr)
    if not measured.any():
        raise ValueError("z has no measured (finite) point")
    z0 = np.where(measured, arr, 0.0)
    scale = float(np.max(np.abs(z0)))
    kernels = _axis_kernels(cutoff, sp, order, 2 * order)
    delta = measured.astype(np.float64)
    mean, _ = _fit(z0, delta, kernels, order)
    c, previous, iterations, converged = None, None, 0, not robust
    while robust and iterations < max_iter:
        residual = np.abs(arr - mean)[measured]
        c = ROBUST_C * float(np.median(residual))
        if c <= 1e-12 * scale:  # the mean line passes through half the points (to rounding)
            converged = True
            break
        delta = np.where(measured, tukey_biweight(np.where(measured, arr - mean, 0.0), c), 0.0)
        new, _ = _fit(z0, delta, kernels, order)
        new = np.where(np.isfinite(new), new, mean)  # a window whose points all lost weight
        iterations += 1
        change = float(np.max(np.abs(new - mean)[measured]))
        mean = new
        if change < tol * c or (previous is not None and abs(c - previous) < tol * c):
            converged = True
            break
        previous = c
    mean = np.where(measured, mean, np.nan)
    return RegressionFilter(mean, delta, c, iterations, converged)


def robust_gaussian_filter(z, spacing, cutoff, *, order=2):
    """The robust Gaussian regression mean line (ISO 16610-31 profile, -71 surface) as an
    array; :func:`regression_filter` for the weights and the iterations."""
    return regression_filter(z, spacing, cutoff, order=order, robust=True).mean


def robust_l_filter(z, spacing, nesting_index, *, order=2):
    """``z`` minus its robust Gaussian regression mean line: the roughness (SL) surface of
    the robust L-filter, whose mean line does not follow spikes, pits and deep valleys."""
    arr = height_map(z)
    return arr - robust_gaussian_filter(arr, spacing, nesting_index, order=order)
