r"""Height and material-ratio texture parameters, and the conventions of every texture module.

* Profiles (1-D ``z[ix]``): ISO 4287:1997 ``Ra, Rq, Rsk, Rku, Rp, Rv, Rt`` and the
  ISO 13565-2:1996 material-ratio set ``Rk, Rpk, Rvk, Mr1, Mr2``.
* Surfaces (2-D ``z[iy, ix]``): ISO 25178-2:2012 height (4.1) and material-ratio (4.4:
  ``Sk, Spk, Svk, Smr1, Smr2``, the ISO 13565-2 construction applied to the areal curve)
  parameters.

The spatial (Sal, Str), texture-direction (Std) and spacing (RSm) parameters and the whole
parameter sets are in :mod:`roughgp.metrology.texture`, which builds on the helpers here
(:func:`as_heights`, :func:`undefined_policy`, :func:`undefined_value`, :func:`is_flat`,
:func:`flat_message`).

Conventions (both modules):

* Heights are referred to their mean (``level=False``) or to a least-squares plane / line
  (``level=True``). The standards evaluate the S-F (areal) or filtered roughness (profile)
  surface; no form removal beyond the plane and no filtering is done here, and a profile
  is evaluated over its whole length as ONE evaluation length (no sampling-length split).
* Lengths are in the unit of ``spacing`` (scalar or ``(dy, dx)`` in array order, see
  :mod:`roughgp.common.grid`), heights in the unit of ``z``, material ratios in percent.
* Angles are reported in DEGREES, counter-clockwise from the x-axis in the library's
  ``(x, y) = (ix * dx, iy * dy)`` coordinates (the radians of :mod:`roughgp.gp.acvf` times
  180 / pi), folded to (-90, 90].
* A parameter that the data do not define (a flat surface has no skewness; an ACF that
  never decays to 0.2 within the field has no Sal) raises :class:`UndefinedParameterError`
  (a ``ValueError``) that says why. ``undefined="nan"`` asks for ``float('nan')`` in its
  place instead; nothing else ever returns NaN.
"""

from __future__ import annotations

import math

import numpy as np

from roughgp.common.checks import check_finite

__all__ = ["UndefinedParameterError", "EQUIVALENCE_WIDTH", "CURVE_KEYS", "as_heights",
           "undefined_policy", "undefined_value", "is_flat", "flat_message", "residual_heights",
           "amplitude_parameters", "height_parameters", "material_ratio_curve",
           "curve_parameters", "material_ratio_parameters"]

EQUIVALENCE_WIDTH = 40.0  # material-ratio width of the central region, ISO 13565-2 (percent)
_FLAT = 1e-12  # Sq below this fraction of max|z| counts as zero height variance


class UndefinedParameterError(ValueError):
    """A texture parameter that the data do not define (zero height variance, an ACF that
    does not decay to the threshold within the field, no complete profile element)."""


# --------------------------------------------------------------------------- input, levelling

def as_heights(z, ndim, what):
    """``z`` as float64 heights: ``ndim`` (a tuple of 1 and/or 2) dimensions, at least 3 points
    per axis, finite; errors name ``what`` (the function asking)."""
    z = np.asarray(z, dtype=np.float64)
    if z.ndim not in ndim:
        want = " or ".join({1: "a profile (n,)", 2: "a surface (ny, nx)"}[d] for d in ndim)
        raise ValueError(f"z must be {want} for {what}, got shape {z.shape}")
    if min(z.shape) < 3:
        raise ValueError(f"z must have at least 3 points per axis for {what}, got shape "
                         f"{z.shape}")
    check_finite("z", z)
    return z


def undefined_policy(undefined):
    """``undefined``, checked to be ``"raise"`` or ``"nan"``."""
    if undefined not in ("raise", "nan"):
        raise ValueError(f"undefined must be 'raise' or 'nan', got {undefined!r}")
    return undefined


def undefined_value(undefined, message):
    """Raise :class:`UndefinedParameterError`, or return NaN when the caller asked for it."""
    if undefined_policy(undefined) == "raise":
        raise UndefinedParameterError(message)
    return math.nan


def is_flat(h, z):
    """Whether the residual heights ``h`` of ``z`` have zero variance (to rounding)."""
    top = float(np.max(np.abs(z)))
    if top == 0:
        return True
    u = h / top  # scaled: the squares of heights of 1e200 would overflow
    return math.sqrt(np.mean(u * u)) <= _FLAT


def flat_message(names):
    """The message that the parameters ``names`` are undefined for zero height variance."""
    return (f"z has zero height variance (Sq = 0 after removing the mean or plane): "
            f"{', '.join(names)} are undefined")


def residual_heights(z, level=False):
    """Heights referred to the mean (``level=False``) or to the least-squares plane (surface)
    or line (profile) (``level=True``). A plane fit does not depend on the spacing."""
    z = as_heights(z, (1, 2), "residual_heights")
    if not level:
        return z - z.mean()
    axes = np.meshgrid(*[np.arange(n) - (n - 1) / 2 for n in z.shape], indexing="ij")
    design = np.stack([np.ones(z.size)] + [a.ravel() for a in axes], axis=1)
    coef = np.linalg.lstsq(design, z.ravel(), rcond=None)[0]
    return z - (design @ coef).reshape(z.shape)


# --------------------------------------------------------------------------- height parameters

def unit_heights(h):
    """``(h / scale, scale)`` with ``scale = max |h|`` (1 for all zeros): powers of the scaled
    heights stay finite for any finite ``h`` (heights of 1e200 would overflow their squares)."""
    scale = float(np.max(np.abs(h))) if h.size else 0.0
    scale = scale if scale > 0 else 1.0
    return h / scale, scale


def amplitude_parameters(h, p):
    """``{p}a, {p}q, {p}p, {p}v`` and ``Sz`` (``p = "S"``) or ``Rt`` of residual heights ``h``."""
    # 0.0 + : a flat surface's heights are +0, whose negation -0 would print as "Sv -0"
    peak, valley = 0.0 + float(h.max()), 0.0 + float(-h.min())
    u, scale = unit_heights(h)
    return {f"{p}a": float(np.mean(np.abs(h))), f"{p}q": scale * math.sqrt(np.mean(u * u)),
            f"{p}p": peak, f"{p}v": valley, f"{p}{'z' if p == 'S' else 't'}": peak + valley}


def _moments(h, p):
    h = unit_heights(h)[0]  # the ratios do not depend on the scale
    q2 = np.mean(h * h)
    return {f"{p}sk": float(np.mean(h**3) / q2**1.5), f"{p}ku": float(np.mean(h**4) / q2**2)}


def height_parameters(z, level=False, undefined="raise"):
    r"""Height parameters: ISO 25178-2:2012 4.1 for a surface, ISO 4287:1997 4.1-4.2 for a profile.

    With residual heights :math:`h` (see :func:`residual_heights`): ``Sa`` = mean
    :math:`|h|`, ``Sq`` = rms :math:`h`, ``Sp`` = max :math:`h`, ``Sv`` = -min :math:`h`
    (positive), ``Sz = Sp + Sv``, ``Ssk`` = mean :math:`h^3/S_q^3`, ``Sku`` = mean
    :math:`h^4/S_q^4`. A profile gives ``Ra, Rq, Rp, Rv, Rt, Rsk, Rku`` the same way, over
    the whole profile (``Rt = Rp + Rv`` of the evaluation length; ISO 4287's ``Rp, Rv, Rz``
    per sampling length are not computed).

    Returns:
        dict keyed by the ISO symbols. ``Ssk``/``Sku`` are undefined for zero height variance
        (a plane with ``level=True``): see ``undefined`` in the module docstring.
    """
    p = "S" if np.ndim(z) == 2 else "R"
    undefined_policy(undefined)
    h = residual_heights(z, level)
    out = amplitude_parameters(h, p)
    if is_flat(h, z):
        nan = undefined_value(undefined, flat_message([f"{p}sk", f"{p}ku"]))
        return {**out, f"{p}sk": nan, f"{p}ku": nan}
    return {**out, **_moments(h, p)}


# --------------------------------------------------------------------------- material ratio

def material_ratio_curve(z, n_points=10001):
    r"""Material ratio (Abbott-Firestone) curve, ISO 25178-2:2012 4.4.1 / ISO 4287 4.5.1.

    ``Smr(c)`` is the percentage of the points at height :math:`\ge c`; its inverse is
    sampled at ``n_points`` equally spaced ratios: ``heights[i]`` is the
    ``1 - ratio[i] / 100`` quantile of ``z`` with linear interpolation between order
    statistics (``numpy.quantile``'s default), so ``heights[0] = max z`` at 0 % and
    ``heights[-1] = min z`` at 100 %. Heights are those of ``z`` as given (no mean removed).

    Returns:
        ``(ratio, heights)``, both of shape (n_points,): ratio in percent, increasing;
        heights non-increasing.
    """
    z = as_heights(z, (1, 2), "material_ratio_curve")
    if not isinstance(n_points, (int, np.integer)) or n_points < 101:
        raise ValueError(f"n_points must be an integer >= 101, got {n_points!r}")
    ratio = np.linspace(0.0, 100.0, int(n_points))
    return ratio, np.quantile(z.ravel(), 1.0 - ratio / 100.0)


def _check_curve(ratio, heights):
    ratio, heights = np.asarray(ratio, float), np.asarray(heights, float)
    if ratio.ndim != 1 or ratio.shape != heights.shape or ratio.size < 101:
        raise ValueError(f"ratio and heights must be 1-D of the same length >= 101, got "
                         f"shapes {ratio.shape} and {heights.shape}")
    check_finite("ratio", ratio)
    check_finite("heights", heights)
    if ratio[0] != 0 or ratio[-1] != 100 or np.any(np.diff(ratio) <= 0):
        raise ValueError("ratio must increase from 0 to 100 (percent)")
    if np.any(np.diff(heights) > 0):
        raise ValueError("heights must be non-increasing (a material ratio curve)")
    return ratio, heights


def _equivalent_line(ratio, heights, line):
    """Slope and intercept of the ISO 13565-2 equivalent straight line: the 40 % wide window
    whose secant has the least gradient (the first one on ties), then either that secant or
    the least-squares line through the curve points in the window."""
    starts = ratio[ratio <= 100.0 - EQUIVALENCE_WIDTH + 1e-9]
    secant = (np.interp(starts + EQUIVALENCE_WIDTH, ratio, heights)
              - heights[:starts.size]) / EQUIVALENCE_WIDTH
    # gradients are <= 0: the largest is the least steep; the first on ties (to rounding)
    tie = 1e-9 * (heights[0] - heights[-1]) / EQUIVALENCE_WIDTH
    i = int(np.argmax(secant >= secant.max() - tie))
    if line == "secant":
        return secant[i], heights[i] - secant[i] * ratio[i]
    window = (ratio >= ratio[i]) & (ratio <= ratio[i] + EQUIVALENCE_WIDTH + 1e-9)
    slope, intercept = np.polyfit(ratio[window], heights[window], 1)
    return slope, intercept


def curve_parameters(ratio, heights, line="least_squares"):
    r"""ISO 13565-2:1996 parameters of a material ratio curve (areal: ISO 25178-2:2012 4.4).

    The equivalent straight line is fitted to the central region: the 40 % wide window of
    material ratio whose secant has the least gradient. ``line="least_squares"`` (default)
    takes the least-squares line through the curve in that window, as ISO 13565-2 and
    surfalize do; ``line="secant"`` takes the secant itself. Its heights at 0 % and 100 %
    bound the core: ``k`` (Sk, Rk) is their difference, ``mr1``/``mr2`` (Smr1/Smr2,
    Mr1/Mr2, percent) are the ratios where the curve crosses them, and ``pk`` (Spk, Rpk) and
    ``vk`` (Svk, Rvk) are the heights of the triangles with bases ``mr1`` and
    ``100 - mr2`` whose areas equal the areas of the curve above the core (peaks) and below
    it (valleys): :math:`pk = 2A_1/mr_1`, :math:`vk = 2A_2/(100-mr_2)` (0 for an empty zone).

    Args:
        ratio, heights: a curve as from :func:`material_ratio_curve` (ratio in percent).
        line: ``"least_squares"`` or ``"secant"``.

    Returns:
        dict with keys ``k, pk, vk, mr1, mr2``.
    """
    if line not in ("least_squares", "secant"):
        raise ValueError(f"line must be 'least_squares' or 'secant', got {line!r}")
    ratio, heights = _check_curve(ratio, heights)
    slope, upper = _equivalent_line(ratio, heights, line)
    lower = upper + 100.0 * slope
    rising_h, rising_r = heights[::-1], ratio[::-1]
    mr1 = float(np.interp(upper, rising_h, rising_r))
    mr2 = float(np.interp(lower, rising_h, rising_r))
    # areas between the (piecewise linear) curve and the core limits, cut exactly at mr1, mr2
    peak = ratio < mr1
    peak_area = np.trapezoid(np.append(heights[peak] - upper, 0.0), np.append(ratio[peak], mr1))
    valley = ratio > mr2
    valley_area = np.trapezoid(np.insert(lower - heights[valley], 0, 0.0),
                               np.insert(ratio[valley], 0, mr2))
    return {"k": float(upper - lower), "mr1": mr1, "mr2": mr2,
            "pk": float(2 * peak_area / mr1) if mr1 > 0 else 0.0,
            "vk": float(2 * valley_area / (100 - mr2)) if mr2 < 100 else 0.0}


CURVE_KEYS = {"S": ("Sk", "Spk", "Svk", "Smr1", "Smr2"), "R": ("Rk", "Rpk", "Rvk", "Mr1", "Mr2")}


def material_ratio_parameters(z, level=False, n_points=10001, line="least_squares",
                              undefined="raise"):
    """``Sk, Spk, Svk, Smr1, Smr2`` of a surface (ISO 25178-2:2012 4.4) or ``Rk, Rpk, Rvk,
    Mr1, Mr2`` of a profile (ISO 13565-2:1996) from :func:`material_ratio_curve` and
    :func:`curve_parameters`. The profile is not filtered with the ISO 13565-1 filter.
    Undefined for zero height variance."""
    undefined_policy(undefined)
    keys = CURVE_KEYS["S" if np.ndim(z) == 2 else "R"]
    h = residual_heights(z, level)
    if is_flat(h, z):
        return dict.fromkeys(keys, undefined_value(undefined, flat_message(keys)))
    c = curve_parameters(*material_ratio_curve(h, n_points), line=line)
    return dict(zip(keys, (c["k"], c["pk"], c["vk"], c["mr1"], c["mr2"])))
