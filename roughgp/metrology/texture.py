r"""Spatial, texture-direction and spacing parameters, and the whole parameter sets: a
simulated surface judged the way a metrologist judges a measured one.

* Profiles (1-D ``z[ix]``): ISO 4287:1997 ``RSm`` (4.3.1), and :func:`profile_parameters`,
  the set with the height and material-ratio parameters.
* Surfaces (2-D ``z[iy, ix]``): ISO 25178-2:2012 spatial (4.2: ``Sal, Str``) and
  texture-direction (4.5: ``Std``) parameters, and :func:`areal_parameters`, the set with the
  height (4.1) and material-ratio (4.4) parameters.

The height and material-ratio parameters themselves (``height_parameters``,
``material_ratio_parameters``, ...) and the conventions of both modules (levelling, units,
degrees, :class:`~roughgp.metrology.texture_heights.UndefinedParameterError` and
``undefined="nan"``) are in :mod:`roughgp.metrology.texture_heights`.
"""

from __future__ import annotations

import heapq
import math

import numpy as np

from roughgp.common.grid import normalize
from roughgp.metrology import texture_heights as th
from roughgp.metrology.spectral import empirical_acvf

__all__ = ["ACF_THRESHOLD", "DIRECTION_HALF_WIDTH", "autocorrelation", "spatial_parameters",
           "angular_spectrum", "texture_direction", "mean_width", "areal_parameters",
           "profile_parameters"]

ACF_THRESHOLD = 0.2  # s of ISO 25178-2 4.2 (the default of ISO 25178-3)
DIRECTION_HALF_WIDTH = 20.0  # degrees around the spectral maximum used to refine Std


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
    h = th.residual_heights(z, level)
    if th.is_flat(h, z):
        raise th.UndefinedParameterError(th.flat_message(["the autocorrelation function"]))
    lags, acvf = empirical_acvf(th.unit_heights(h)[0], spacing, unbiased=unbiased,
                                demean=False)  # scaled: the normalised ACF does not change
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
    from scipy import ndimage  # here: 0.1-0.15 s that a map with holes (no Sal, Str) skips

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
    th.undefined_policy(undefined)
    if not 0 < s < 1:
        raise ValueError(f"s must be in (0, 1), got {s!r}")
    if not isinstance(n_directions, (int, np.integer)) or n_directions < 8:
        raise ValueError(f"n_directions must be an integer >= 8, got {n_directions!r}")
    z = th.as_heights(z, (2,), "spatial_parameters")
    shape, spacing = normalize(z.shape, spacing)
    h = th.residual_heights(z, level)
    if th.is_flat(h, z):
        nan = th.undefined_value(undefined, th.flat_message(["Sal", "Str"]))
        return {"Sal": nan, "Str": nan}
    lengths = _decay_lengths(autocorrelation(h, spacing)[1], spacing, s, int(n_directions))
    if np.all(np.isnan(lengths)):
        sal = th.undefined_value(undefined, f"the ACF of z does not decay to s = {s} in any "
                                            f"direction within the field: Sal and Str are "
                                            f"undefined (use a larger field)")
        return {"Sal": sal, "Str": sal}
    sal = float(np.nanmin(lengths))
    if np.any(np.isnan(lengths)):
        ratio = th.undefined_value(undefined, f"the ACF of z does not decay to s = {s} within "
                                              f"the field in every direction (a lay longer than "
                                              f"the field): Str is undefined (use a larger field)")
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
    z = th.as_heights(z, (2,), "angular_spectrum")
    (ny, nx), (dy, dx) = normalize(z.shape, spacing)
    window = np.outer(np.hanning(ny), np.hanning(nx))
    power = np.abs(np.fft.fft2(th.residual_heights(z, level) * window)) ** 2
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
    th.undefined_policy(undefined)
    z = th.as_heights(z, (2,), "texture_direction")
    unit = th.unit_heights(z)[0]  # the direction does not depend on the heights' scale
    angles, power = angular_spectrum(unit, spacing, n_angles, level)
    if not power.sum() > 0 or th.is_flat(th.residual_heights(z, level), z):
        return th.undefined_value(undefined, th.flat_message(["Std"]))
    width = 180.0 / n_angles
    from scipy import ndimage

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
    th.undefined_policy(undefined)
    z = th.as_heights(z, (1,), "mean_width")
    (dx,) = normalize(z.shape, spacing)[1]
    h = th.residual_heights(z, level)
    if th.is_flat(h, z):
        return th.undefined_value(undefined, th.flat_message(["RSm"]))
    start, end, height = _runs(h, dx)
    keep = _discriminate(start, end, height, 0.1 * float(np.ptp(h)), 0.01 * (h.size - 1) * dx)
    inner = keep[1:-1]
    pairs = inner.size // 2
    if pairs == 0:
        return th.undefined_value(undefined, "z has no complete profile element (peak and "
                                             "valley between two mean-line crossings): RSm is "
                                             "undefined")
    return float((end[inner[2 * pairs - 1]] - start[inner[0]]) / pairs)


# --------------------------------------------------------------------------- parameter sets

def areal_parameters(z, spacing=1.0, level=False, undefined="raise"):
    """ISO 25178-2:2012 parameters of a surface ``z[iy, ix]``: ``Sa, Sq, Ssk, Sku, Sp, Sv,
    Sz`` (:func:`~roughgp.metrology.texture_heights.height_parameters`), ``Sal, Str``
    (:func:`spatial_parameters`), ``Std`` (:func:`texture_direction`, degrees) and ``Sk, Spk,
    Svk, Smr1, Smr2`` (:func:`~roughgp.metrology.texture_heights.material_ratio_parameters`).

    Args:
        z: surface of shape (ny, nx), at least 3 x 3, finite.
        spacing: scalar or (dy, dx) in array order.
        level: refer heights to the least-squares plane instead of the mean.
        undefined: ``"raise"`` (default) or ``"nan"`` for parameters that the data do not
            define (a flat surface: all but Sa, Sq, Sp, Sv, Sz; an ACF that does not decay
            within the field: Sal and/or Str).
    """
    z = th.as_heights(z, (2,), "areal_parameters")
    normalize(z.shape, spacing)
    th.undefined_policy(undefined)
    h = th.residual_heights(z, level)
    if th.is_flat(h, z):
        names = ["Ssk", "Sku", "Sal", "Str", "Std", *th.CURVE_KEYS["S"]]
        nan = th.undefined_value(undefined, th.flat_message(names))
        return {**th.amplitude_parameters(h, "S"), **dict.fromkeys(names, nan)}
    out = th.height_parameters(h)
    out.update(spatial_parameters(h, spacing, undefined=undefined))
    out["Std"] = texture_direction(h, spacing)
    out.update(th.material_ratio_parameters(h))
    return out


def profile_parameters(z, spacing=1.0, level=False, undefined="raise"):
    """ISO 4287:1997 and ISO 13565-2:1996 parameters of a profile ``z[ix]``: ``Ra, Rq, Rsk,
    Rku, Rp, Rv, Rt`` (:func:`~roughgp.metrology.texture_heights.height_parameters`, over
    the whole profile), ``RSm`` (:func:`mean_width`) and ``Rk, Rpk, Rvk, Mr1, Mr2``
    (:func:`~roughgp.metrology.texture_heights.material_ratio_parameters`). No filtering and
    no sampling-length split is done. Arguments as :func:`areal_parameters`."""
    z = th.as_heights(z, (1,), "profile_parameters")
    normalize(z.shape, spacing)
    th.undefined_policy(undefined)
    h = th.residual_heights(z, level)
    if th.is_flat(h, z):
        names = ["Rsk", "Rku", "RSm", *th.CURVE_KEYS["R"]]
        nan = th.undefined_value(undefined, th.flat_message(names))
        return {**th.amplitude_parameters(h, "R"), **dict.fromkeys(names, nan)}
    out = th.height_parameters(h)
    out["RSm"] = mean_width(h, spacing, undefined=undefined)
    out.update(th.material_ratio_parameters(h))
    return out
