r"""Standard surface-texture parameters: a simulated surface judged the way a metrologist
judges a measured one.

* Profiles (1-D ``z[ix]``): ISO 4287:1997 ``Ra, Rq, Rsk, Rku, Rp, Rv, Rt, RSm`` and the
  ISO 13565-2:1996 material-ratio set ``Rk, Rpk, Rvk, Mr1, Mr2``.
* Surfaces (2-D ``z[iy, ix]``): ISO 25178-2:2012 height (4.1), spatial (4.2: ``Sal, Str``),
  material-ratio (4.4: ``Sk, Spk, Svk, Smr1, Smr2``, the ISO 13565-2 construction applied to
  the areal curve) and texture-direction (4.5: ``Std``) parameters.

Conventions (the whole module):

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

import heapq
import math

import numpy as np
from scipy import ndimage

from roughgp.common.checks import check_finite
from roughgp.common.grid import normalize
from roughgp.metrology.spectral import empirical_acvf

__all__ = ["UndefinedParameterError", "residual_heights", "height_parameters",
           "material_ratio_curve", "curve_parameters", "material_ratio_parameters",
           "autocorrelation", "spatial_parameters", "angular_spectrum", "texture_direction",
           "mean_width", "areal_parameters", "profile_parameters"]

ACF_THRESHOLD = 0.2  # s of ISO 25178-2 4.2 (the default of ISO 25178-3)
EQUIVALENCE_WIDTH = 40.0  # material-ratio width of the central region, ISO 13565-2 (percent)
DIRECTION_HALF_WIDTH = 20.0  # degrees around the spectral maximum used to refine Std
_FLAT = 1e-12  # Sq below this fraction of max|z| counts as zero height variance


class UndefinedParameterError(ValueError):
    """A texture parameter that the data do not define (zero height variance, an ACF that
    does not decay to the threshold within the field, no complete profile element)."""


# --------------------------------------------------------------------------- input, levelling

def _heights(z, ndim, what):
    z = np.asarray(z, dtype=np.float64)
    if z.ndim not in ndim:
        want = " or ".join({1: "a profile (n,)", 2: "a surface (ny, nx)"}[d] for d in ndim)
        raise ValueError(f"z must be {want} for {what}, got shape {z.shape}")
    if min(z.shape) < 3:
        raise ValueError(f"z must have at least 3 points per axis for {what}, got shape "
                         f"{z.shape}")
    check_finite("z", z)
    return z


def _policy(undefined):
    if undefined not in ("raise", "nan"):
        raise ValueError(f"undefined must be 'raise' or 'nan', got {undefined!r}")
    return undefined


def _undefined(undefined, message):
    """Raise :class:`UndefinedParameterError`, or return NaN when the caller asked for it."""
    if _policy(undefined) == "raise":
        raise UndefinedParameterError(message)
    return math.nan


def _is_flat(h, z):
    return math.sqrt(np.mean(h * h)) <= _FLAT * float(np.max(np.abs(z)))


def _flat_message(names):
    return (f"z has zero height variance (Sq = 0 after removing the mean or plane): "
            f"{', '.join(names)} are undefined")


def residual_heights(z, level=False):
    """Heights referred to the mean (``level=False``) or to the least-squares plane (surface)
    or line (profile) (``level=True``). A plane fit does not depend on the spacing."""
    z = _heights(z, (1, 2), "residual_heights")
    if not level:
        return z - z.mean()
    axes = np.meshgrid(*[np.arange(n) - (n - 1) / 2 for n in z.shape], indexing="ij")
    design = np.stack([np.ones(z.size)] + [a.ravel() for a in axes], axis=1)
    coef = np.linalg.lstsq(design, z.ravel(), rcond=None)[0]
    return z - (design @ coef).reshape(z.shape)


# --------------------------------------------------------------------------- height parameters

def _amplitudes(h, p):
    peak, valley = float(h.max()), float(-h.min())
    return {f"{p}a": float(np.mean(np.abs(h))), f"{p}q": math.sqrt(np.mean(h * h)),
            f"{p}p": peak, f"{p}v": valley, f"{p}{'z' if p == 'S' else 't'}": peak + valley}


def _moments(h, p):
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
    _policy(undefined)
    h = residual_heights(z, level)
    out = _amplitudes(h, p)
    if _is_flat(h, z):
        nan = _undefined(undefined, _flat_message([f"{p}sk", f"{p}ku"]))
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
    z = _heights(z, (1, 2), "material_ratio_curve")
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


_CURVE_KEYS = {"S": ("Sk", "Spk", "Svk", "Smr1", "Smr2"), "R": ("Rk", "Rpk", "Rvk", "Mr1", "Mr2")}


def material_ratio_parameters(z, level=False, n_points=10001, line="least_squares",
                              undefined="raise"):
    """``Sk, Spk, Svk, Smr1, Smr2`` of a surface (ISO 25178-2:2012 4.4) or ``Rk, Rpk, Rvk,
    Mr1, Mr2`` of a profile (ISO 13565-2:1996) from :func:`material_ratio_curve` and
    :func:`curve_parameters`. The profile is not filtered with the ISO 13565-1 filter.
    Undefined for zero height variance."""
    _policy(undefined)
    keys = _CURVE_KEYS["S" if np.ndim(z) == 2 else "R"]
    h = residual_heights(z, level)
    if _is_flat(h, z):
        return dict.fromkeys(keys, _undefined(undefined, _flat_message(keys)))
    c = curve_parameters(*material_ratio_curve(h, n_points), line=line)
    return dict(zip(keys, (c["k"], c["pk"], c["vk"], c["mr1"], c["mr2"])))


# --------------------------------------------------------------------------- autocorrelation

def autocorrelation(z, spacing=1.0, level=False, unbiased=True):
    r"""Normalised autocorrelation function of a profile or surface (ISO 25178-2:2012, the
    definition under Sal and Str, 4.2).

    :math:`f_{ACF}(\boldsymbol\tau) = \hat r(\boldsymbol\tau) / \hat r(0)` from
    :func:`roughgp.metrology.spectral.empirical_acvf` of the residual heights. ``unbiased=True``
    divides each lag by its number of overlapping pairs (as surfalize does), so the estimate
    follows the ACF of the process; ``unbiased=False`` is the literal ratio of integrals over
    the field, which the triangle window :math:`\prod_d(1-|\tau_d|/L_d)` shrinks (Sal of an
    exponential ACF with lengthscale 8 on a 256-point field comes out about 3 % shorter).

    Returns:
        ``(lags, acf)``: lags of shape (2ny-1, 2nx-1, 2) in (x, y) order and physical units
        (zero lag at index ``(ny-1, nx-1)``), acf of shape (2ny-1, 2nx-1), 1 at zero lag.
        For a profile, shapes (2n-1, 1) and (2n-1,).
    """
    h = residual_heights(z, level)
    if _is_flat(h, z):
        raise UndefinedParameterError(_flat_message(["the autocorrelation function"]))
    lags, acvf = empirical_acvf(h, spacing, unbiased=unbiased, demean=False)
    return lags, acvf / acvf[tuple(n - 1 for n in h.shape)]


def _decay_lengths(acf, spacing, s, n_directions):
    """Distance from zero lag to the first crossing of ``s`` along each of ``n_directions``
    rays in [0, 180) degrees (the ACF is point-symmetric), NaN where the ray leaves the lag
    grid first. The ACF is interpolated bilinearly; the crossing linearly between ray
    samples a quarter of the finer spacing apart."""
    (dy, dx), (my, mx) = spacing, acf.shape
    cy, cx = (my - 1) // 2, (mx - 1) // 2
    theta = np.arange(n_directions) * math.pi / n_directions
    per_y, per_x = np.sin(theta) / dy, np.cos(theta) / dx  # index steps per unit length
    with np.errstate(divide="ignore"):
        reach = np.minimum(cy / np.abs(per_y), cx / np.abs(per_x))
    step = 0.25 * min(dx, dy)
    r = np.arange(int(np.ceil(reach.max() / step)) + 1) * step
    coords = [cy + r * per_y[:, None], cx + r * per_x[:, None]]
    values = ndimage.map_coordinates(acf, coords, order=1, mode="nearest")
    below = (values <= s) & (r <= reach[:, None])
    first = np.argmax(below, axis=1)
    rows = np.arange(n_directions)
    v0, v1 = values[rows, first - 1], values[rows, first]
    lengths = r[first - 1] + step * (v0 - s) / (v0 - v1)
    return np.where(below.any(axis=1) & (first > 0), lengths, np.nan)


def spatial_parameters(z, spacing=1.0, level=False, s=ACF_THRESHOLD, n_directions=360,
                       undefined="raise"):
    r"""Autocorrelation length ``Sal`` and texture aspect ratio ``Str``, ISO 25178-2:2012
    4.2.1 and 4.2.2.

    Along ``n_directions`` rays from zero lag, the decay length is the distance at which
    :func:`autocorrelation` first falls to ``s`` (0.2). ``Sal`` is the shortest decay
    length (fastest decay), ``Str`` the shortest over the longest, in (0, 1]: near 1 for an
    isotropic surface, small for a strong lay. Distances are in physical units, so
    ``dy != dx`` is handled.

    Undefined (see ``undefined``): both for zero height variance; ``Sal`` when the ACF
    decays to ``s`` in no direction within the field; ``Str`` when it does not decay in
    some direction (a lay much longer than the field: the longest decay length is unknown).
    surfalize finds the same crossings on the edge of the region above ``s`` with cubic
    interpolation; on the test surfaces the two agree to a few percent.
    """
    _policy(undefined)
    if not 0 < s < 1:
        raise ValueError(f"s must be in (0, 1), got {s!r}")
    if not isinstance(n_directions, (int, np.integer)) or n_directions < 8:
        raise ValueError(f"n_directions must be an integer >= 8, got {n_directions!r}")
    z = _heights(z, (2,), "spatial_parameters")
    shape, spacing = normalize(z.shape, spacing)
    h = residual_heights(z, level)
    if _is_flat(h, z):
        nan = _undefined(undefined, _flat_message(["Sal", "Str"]))
        return {"Sal": nan, "Str": nan}
    lengths = _decay_lengths(autocorrelation(h, spacing)[1], spacing, s, int(n_directions))
    if np.all(np.isnan(lengths)):
        sal = _undefined(undefined, f"the ACF of z does not decay to s = {s} in any "
                                    f"direction within the field: Sal and Str are undefined "
                                    f"(use a larger field)")
        return {"Sal": sal, "Str": sal}
    sal = float(np.nanmin(lengths))
    if np.any(np.isnan(lengths)):
        ratio = _undefined(undefined, f"the ACF of z does not decay to s = {s} within the "
                                      f"field in every direction (a lay longer than the field):"
                                      f" Str is undefined (use a larger field)")
    else:
        ratio = sal / float(lengths.max())
    return {"Sal": sal, "Str": ratio}


# --------------------------------------------------------------------------- texture direction

def angular_spectrum(z, spacing=1.0, n_angles=180, level=False):
    r"""Power of the surface in angular sectors, indexed by the LAY direction it produces.

    The residual heights are multiplied by a separable Hann window (without it the
    non-periodic edges put spurious lines on the frequency axes) and transformed; each
    frequency :math:`\boldsymbol f = (f_x, f_y)` in physical units is a wave whose crests
    run at the angle of :math:`\boldsymbol f` minus 90 degrees, and its periodogram power is
    shared linearly between the two nearest of ``n_angles`` sector centres of that crest
    angle. So a lay at angle :math:`\phi` shows as a lobe at :math:`\phi`, and a
    cross-hatched (honed) surface as two lobes at :math:`\pm\phi`. This is the angular
    spectrum of ISO 25178-2:2012 (the power integrated over the frequency radius in each
    sector, the basis of Std in 4.5) turned by 90 degrees, so that its maximum IS the
    texture direction Std.

    Returns:
        ``(angles, power)`` of shape (n_angles,): sector centres in degrees in (-90, 90]
        (increasing), and power that sums to the variance of the windowed heights over the
        mean square of the window (an estimate of :math:`S_q^2`, the window's loss undone).
    """
    if not isinstance(n_angles, (int, np.integer)) or not 18 <= n_angles <= 3600:
        raise ValueError(f"n_angles must be an integer in [18, 3600], got {n_angles!r}")
    z = _heights(z, (2,), "angular_spectrum")
    (ny, nx), (dy, dx) = normalize(z.shape, spacing)
    window = np.outer(np.hanning(ny), np.hanning(nx))
    power = np.abs(np.fft.fft2(residual_heights(z, level) * window)) ** 2
    power *= 1.0 / (z.size**2 * np.mean(window**2))
    power[0, 0] = 0.0
    crest = np.degrees(np.arctan2(np.fft.fftfreq(ny, dy)[:, None],
                                  np.fft.fftfreq(nx, dx)[None, :])) - 90.0
    width = 180.0 / n_angles
    position = np.mod((crest + 90.0) / width - 1.0, n_angles)  # sector k centred at k
    lower = np.floor(position).astype(int)
    frac = position - lower
    sectors = (np.bincount(lower.ravel() % n_angles, (power * (1 - frac)).ravel(), n_angles)
               + np.bincount((lower.ravel() + 1) % n_angles, (power * frac).ravel(), n_angles))
    return -90.0 + width * np.arange(1, n_angles + 1), sectors


def _fold(angle):
    """Angle in degrees folded to (-90, 90] (a direction, period 180)."""
    return 90.0 - np.mod(90.0 - angle, 180.0)


def texture_direction(z, spacing=1.0, n_angles=180, level=False, undefined="raise"):
    r"""Texture direction ``Std`` in degrees in (-90, 90], ISO 25178-2:2012 4.5.1.

    ``Std`` is the direction of the LAY (the grooves), counter-clockwise from the x-axis in
    the library's (x, y) = (ix dx, iy dy) coordinates: the maximum of
    :func:`angular_spectrum`. The maximum of the spectrum (smoothed over 2 degrees) is
    refined by the power-weighted circular mean (of doubled angles) of the sectors within
    20 degrees of it, which reads a lay to a fraction of a degree on a 256 x 256 field;
    two lays less than 40 degrees apart are not resolved. For an isotropic surface Std
    exists but carries no information.

    Differences: ISO 25178-2 takes the angle of the maximum of the angular spectrum of the
    frequencies, which is perpendicular to the lay. surfalize 0.19.2 does so too (angular
    amplitude, 0.5 degree bins, no window) with its y axis pointing up the displayed map,
    i.e. against the row index: its Std reads ``(90 - Std) mod 180`` (60 for a lay at 30).
    """
    _policy(undefined)
    angles, power = angular_spectrum(z, spacing, n_angles, level)
    if not power.sum() > 0 or _is_flat(residual_heights(z, level), z):
        return _undefined(undefined, _flat_message(["Std"]))
    width = 180.0 / n_angles
    peak = angles[np.argmax(ndimage.gaussian_filter1d(power, 2.0 / width, mode="wrap"))]
    offset = _fold(angles - peak)
    near = np.abs(offset) <= DIRECTION_HALF_WIDTH
    mean = np.sum(power[near] * np.exp(2j * np.radians(offset[near])))
    return float(_fold(peak + np.degrees(np.angle(mean)) / 2))


# --------------------------------------------------------------------------- profile spacing

def _runs(h, dx):
    """Parts of the profile between mean-line crossings (crossings interpolated linearly):
    start, end and largest |h| of each, alternating in sign."""
    above = h >= 0
    idx = np.flatnonzero(above[:-1] != above[1:])
    cross = (idx + h[idx] / (h[idx] - h[idx + 1])) * dx
    bounds = np.concatenate([[0.0], cross, [(h.size - 1) * dx]])
    height = np.maximum.reduceat(np.abs(h), np.concatenate([[0], idx + 1]))
    return bounds[:-1].copy(), bounds[1:].copy(), height.astype(float)


def _discriminate(start, end, height, min_height, min_width):
    """Merge every interior run lower than ``min_height`` or narrower than ``min_width``
    with its two neighbours, weakest first (a doubly linked list and a heap); the two runs
    cut by the profile ends are never removed. Returns the indices of the surviving runs."""
    k = start.size
    prev, nxt = np.arange(k) - 1, np.arange(k) + 1
    alive = np.ones(k, bool)

    def invalid(j):
        return (prev[j] >= 0 and nxt[j] < k
                and (height[j] < min_height or end[j] - start[j] < min_width))

    heap = [(height[j], j) for j in range(k) if invalid(j)]
    heapq.heapify(heap)
    while heap:
        _, j = heapq.heappop(heap)
        if not alive[j] or not invalid(j):
            continue
        a, b = prev[j], nxt[j]
        end[a], height[a] = end[b], max(height[a], height[b])
        alive[j] = alive[b] = False
        nxt[a] = nxt[b]
        if nxt[b] < k:
            prev[nxt[b]] = a
        if invalid(a):
            heapq.heappush(heap, (height[a], a))
    return np.flatnonzero(alive)


def mean_width(z, spacing=1.0, level=False, undefined="raise"):
    r"""Mean width of the profile elements ``RSm``, ISO 4287:1997 4.3.1.

    A profile element is a profile peak (the part above the mean line between two
    crossings) with the adjacent valley. Peaks or valleys lower than 10 % of ``Rt`` or
    narrower than 1 % of the profile length ((n - 1) dx) are not elements of their own: they
    are merged with their neighbours, weakest first (ISO 4287 uses 10 % of Rz and 1 % of the
    sampling length; here the whole profile is one length). The parts cut by the profile
    ends are dropped, the remaining peaks and valleys are paired in order, and ``RSm`` is
    the mean width of the pairs. A sinusoid of period L gives L.

    Undefined (see ``undefined``) for zero variance or when no complete element remains.
    """
    _policy(undefined)
    z = _heights(z, (1,), "mean_width")
    (dx,) = normalize(z.shape, spacing)[1]
    h = residual_heights(z, level)
    if _is_flat(h, z):
        return _undefined(undefined, _flat_message(["RSm"]))
    start, end, height = _runs(h, dx)
    keep = _discriminate(start, end, height, 0.1 * float(np.ptp(h)), 0.01 * (h.size - 1) * dx)
    inner = keep[1:-1]
    pairs = inner.size // 2
    if pairs == 0:
        return _undefined(undefined, "z has no complete profile element (peak and valley "
                                     "between two mean-line crossings): RSm is undefined")
    return float((end[inner[2 * pairs - 1]] - start[inner[0]]) / pairs)


# --------------------------------------------------------------------------- parameter sets

def areal_parameters(z, spacing=1.0, level=False, undefined="raise"):
    """ISO 25178-2:2012 parameters of a surface ``z[iy, ix]``: ``Sa, Sq, Ssk, Sku, Sp, Sv,
    Sz`` (:func:`height_parameters`), ``Sal, Str`` (:func:`spatial_parameters`), ``Std``
    (:func:`texture_direction`, degrees) and ``Sk, Spk, Svk, Smr1, Smr2``
    (:func:`material_ratio_parameters`).

    Args:
        z: surface of shape (ny, nx), at least 3 x 3, finite.
        spacing: scalar or (dy, dx) in array order.
        level: refer heights to the least-squares plane instead of the mean.
        undefined: ``"raise"`` (default) or ``"nan"`` for parameters that the data do not
            define (a flat surface: all but Sa, Sq, Sp, Sv, Sz; an ACF that does not decay
            within the field: Sal and/or Str).
    """
    z = _heights(z, (2,), "areal_parameters")
    normalize(z.shape, spacing)
    _policy(undefined)
    h = residual_heights(z, level)
    if _is_flat(h, z):
        names = ["Ssk", "Sku", "Sal", "Str", "Std", *_CURVE_KEYS["S"]]
        return {**_amplitudes(h, "S"), **dict.fromkeys(names, _undefined(undefined,
                                                                         _flat_message(names)))}
    out = height_parameters(h)
    out.update(spatial_parameters(h, spacing, undefined=undefined))
    out["Std"] = texture_direction(h, spacing)
    out.update(material_ratio_parameters(h))
    return out


def profile_parameters(z, spacing=1.0, level=False, undefined="raise"):
    """ISO 4287:1997 and ISO 13565-2:1996 parameters of a profile ``z[ix]``: ``Ra, Rq, Rsk,
    Rku, Rp, Rv, Rt`` (:func:`height_parameters`, over the whole profile), ``RSm``
    (:func:`mean_width`) and ``Rk, Rpk, Rvk, Mr1, Mr2`` (:func:`material_ratio_parameters`).
    No filtering and no sampling-length split is done. Arguments as
    :func:`areal_parameters`."""
    z = _heights(z, (1,), "profile_parameters")
    normalize(z.shape, spacing)
    _policy(undefined)
    h = residual_heights(z, level)
    if _is_flat(h, z):
        names = ["Rsk", "Rku", "RSm", *_CURVE_KEYS["R"]]
        return {**_amplitudes(h, "R"), **dict.fromkeys(names, _undefined(undefined,
                                                                         _flat_message(names)))}
    out = height_parameters(h)
    out["RSm"] = mean_width(h, spacing, undefined=undefined)
    out.update(material_ratio_parameters(h))
    return out
