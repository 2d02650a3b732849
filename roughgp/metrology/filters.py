"""ISO Gaussian filters for measured profiles and surfaces, and the S-F-L chain.

* :func:`gaussian_filter` -- the Gaussian mean line of ISO 16610-21 (profile, ``z[ix]``) and
  the areal Gaussian filter of ISO 16610-61 (surface, ``z[iy, ix]``): weighting function
  ``s(x) = 1 / (alpha lambda_c) exp(-pi (x / (alpha lambda_c))**2)`` with
  ``alpha = sqrt(ln 2 / pi)``, so a sine of wavelength ``lambda`` keeps
  ``exp(-pi (alpha lambda_c / lambda)**2)`` of its amplitude in the mean line -- 50 % at the
  cut-off (the nesting index). The areal filter is the product of two such profile
  filters (one per axis, each with its own spacing; ISO 16610-61's isotropic Gaussian).
  The sampled kernel is truncated at ``+/- truncate`` cut-offs (default 1, where the weight
  is 6.5e-7 of its peak) and normalised to sum 1.
* NaN-aware by normalised convolution: the heights with NaN set to 0 and the indicator of
  the measured points are filtered alike and divided, so a hole takes no weight and does
  not bias its neighbours; NaN stays NaN. The same normalised convolution handles the
  borders (the kernel is cut at the field's edge and renormalised: the zero-order end
  correction of ISO 16610-28); ``edge="drop"`` instead sets the band of one kernel
  half-width (``truncate`` cut-offs) along the borders to NaN.
* :func:`s_filter` (ISO 25178-3 S-filter: removes the wavelengths shorter than the S
  nesting index, returns the smoothed surface) and :func:`l_filter` (L-filter: returns the
  surface minus its long-wavelength part, the SL / roughness surface).
* :func:`default_cutoffs` -- profile: ISO 4288 Table 1 / 2 (lambda_c from the Ra or RSm of
  the unfiltered, levelled profile) with the ISO 3274 lambda_s paired with it; surface:
  ISO 25178-3's preferred nesting indices (the 0.8-2.5-8 series) with the L nesting index
  the largest that fits five times on the shorter side, and S the smallest that is at
  least 3 sampling spacings and at least the ISO 3274 partner of L.
* :func:`surface_texture` -- the whole chain: F-operator (:mod:`roughgp.metrology.form`),
  S-filter, L-filter, with a list of the operators applied.

Implemented with FFT convolution along each axis
(:func:`roughgp.common.convolution.convolve_same`): a 1000 x 1000 surface with a 0.8 mm
cut-off at 1 um spacing filters in well under a second.
Lengths (spacing, cut-offs) share one unit, micrometres in roughgp.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from roughgp.common.checks import check_positive, height_map
from roughgp.common.convolution import convolve_same
from roughgp.common.grid import normalize
from roughgp.metrology.form import FormFit, remove_form
from roughgp.metrology.levelling import level
from roughgp.metrology.texture import mean_width

__all__ = ["ALPHA", "PROFILE_CUTOFFS", "PREFERRED_NESTING_INDICES", "gaussian_kernel",
           "check_cutoff", "gaussian_filter", "s_filter", "l_filter", "transmission", "Cutoffs",
           "default_cutoffs", "Texture", "surface_texture"]

#: alpha of ISO 16610-21: the Gaussian's 50 % transmission at the cut-off.
ALPHA = math.sqrt(math.log(2.0) / math.pi)

#: ISO 4288 Table 1 (non-periodic: Ra in um) and Table 2 (periodic: RSm in mm) with the
#: ISO 3274 lambda_s: (lambda_c um, lambda_s um, Ra upper bound um, RSm upper bound um).
PROFILE_CUTOFFS = ((80.0, 2.5, 0.02, 40.0), (250.0, 2.5, 0.1, 130.0),
                   (800.0, 2.5, 2.0, 400.0), (2500.0, 8.0, 10.0, 1300.0),
                   (8000.0, 25.0, math.inf, math.inf))

#: ISO 25178-3 preferred nesting indices (um), the 0.8 - 2.5 - 8 series from 0.08 um to 80 mm.
PREFERRED_NESTING_INDICES = tuple(m * 10.0 ** k for k in range(-1, 5) for m in (0.8, 2.5, 8.0))


def check_cutoff(name, cutoff, spacing):
    """``cutoff`` as a float, or a ``ValueError`` naming ``name`` unless it is >= 2 spacings."""
    check_positive(name, cutoff)
    cutoff = float(cutoff)
    if cutoff < 2.0 * float(np.max(spacing)):
        raise ValueError(f"{name} must be at least 2 sampling spacings (allowed range: "
                         f"[{2.0 * float(np.max(spacing)):g}, inf)), got {cutoff:g}")
    return cutoff


def gaussian_kernel(cutoff, spacing, truncate=1.0):
    """The sampled ISO 16610-21 weighting function at ``k * spacing`` for
    ``|k * spacing| <= truncate * cutoff``, normalised to sum 1 (a 1-D array, odd length)."""
    half = int(math.floor(truncate * cutoff / spacing))
    x = np.arange(-half, half + 1) * spacing
    w = np.exp(-math.pi * (x / (ALPHA * cutoff)) ** 2)
    return w / w.sum()


def transmission(wavelength, cutoff):
    """Amplitude transmission of the Gaussian mean line for a sine of ``wavelength``:
    ``exp(-pi (alpha cutoff / wavelength)**2)`` (the L-filter's is one minus it)."""
    return np.exp(-math.pi * (ALPHA * np.asarray(cutoff) / np.asarray(wavelength)) ** 2)


def gaussian_filter(z, spacing, cutoff, *, edge="normalised", truncate=1.0):
    """The Gaussian mean line (profile, ISO 16610-21) or mean surface (ISO 16610-61).

    Args:
        z: a profile ``z[ix]`` or surface ``z[iy, ix]``; NaN marks unmeasured points.
        spacing: scalar or ``(dy, dx)``, > 0.
        cutoff: the cut-off wavelength / nesting index (same unit), >= 2 spacings.
        edge: ``"normalised"`` (normalised convolution up to the border) or ``"drop"``
            (NaN within ``truncate * cutoff`` of the border).
        truncate: kernel half-width in cut-offs, >= 0.5.

    Returns:
        The long-wavelength part (a new array of the shape of ``z``), NaN where ``z`` is NaN.
    """
    arr = height_map(z)
    _, sp = normalize(arr.shape, spacing)
    cutoff = check_cutoff("cutoff", cutoff, sp)
    check_positive("truncate", truncate)
    if truncate < 0.5:
        raise ValueError(f"truncate must be >= 0.5 cut-offs (allowed range: [0.5, inf)), "
                         f"got {truncate!r}")
    if edge not in ("normalised", "drop"):
        raise ValueError(f"edge must be 'normalised' or 'drop', got {edge!r}")
    measured = np.isfinite(arr)
    num = np.where(measured, arr, 0.0)
    den = measured.astype(np.float64)
    for axis, d in enumerate(sp):
        k = gaussian_kernel(cutoff, d, truncate)
        num = convolve_same(num, k, axis)
        if not measured.all():
            den = convolve_same(den, k, axis)
        else:  # separable: the weights of a full field are a product of 1-D sums
            den = den * convolve_same(np.ones(arr.shape[axis]), k).reshape(
                [-1 if a == axis else 1 for a in range(arr.ndim)])
    with np.errstate(invalid="ignore", divide="ignore"):
        out = num / den
    out[~measured | (den < 1e-9)] = np.nan
    if edge == "drop":
        for axis, d in enumerate(sp):
            half = int(math.floor(truncate * cutoff / d))
            index = [slice(None)] * arr.ndim
            index[axis] = slice(0, half)
            out[tuple(index)] = np.nan
            index[axis] = slice(max(arr.shape[axis] - half, 0), None)
            out[tuple(index)] = np.nan
    return out


def s_filter(z, spacing, nesting_index, *, edge="normalised"):
    """ISO 25178-3 S-filter (Gaussian): the surface without the wavelengths shorter than
    ``nesting_index`` (the smoothed surface)."""
    return gaussian_filter(z, spacing, nesting_index, edge=edge)


def l_filter(z, spacing, nesting_index, *, edge="normalised"):
    """ISO 25178-3 L-filter (Gaussian): ``z`` minus its long-wavelength part, i.e. the SL
    (roughness) surface for wavelengths up to ``nesting_index``."""
    arr = height_map(z)
    return arr - gaussian_filter(arr, spacing, nesting_index, edge=edge)


# --------------------------------------------------------------------------- defaults

@dataclass(frozen=True)
class Cutoffs:
    """A choice of S and L nesting indices (um; None: that filter off) and why."""

    s: float | None
    l: float | None
    reason: str


def _fmt(length):
    return f"{length / 1000:g} mm" if length >= 1000 else f"{length:g} um"


def default_cutoffs(z, spacing=1.0, *, by="Ra"):
    """Default S and L nesting indices for ``z`` (lengths in um).

    Profile (1-D): ISO 4288 -- lambda_c from the Ra (``by="Ra"``, non-periodic profiles,
    Table 1) or the RSm (``by="RSm"``, periodic, Table 2) of the levelled, unfiltered
    profile, refined once with Ra / RSm of the roughness profile at that cut-off; lambda_s
    the ISO 3274 partner (2.5, 2.5, 2.5, 8, 25 um). Surface (2-D): the largest preferred
    nesting index (:data:`PREFERRED_NESTING_INDICES`) <= one fifth of the shorter side for
    L; for S the smallest preferred value >= 3 spacings and >= the ISO 3274 partner of L.
    An S below 2 spacings, or not below L / 3, is switched off (None).
    """
    arr = height_map(z)
    _, sp = normalize(arr.shape, spacing)
    dmax = float(np.max(sp))
    notes = []
    if arr.ndim == 1:
        if by not in ("Ra", "RSm"):
            raise ValueError(f"by must be 'Ra' or 'RSm', got {by!r}")
        profile = level(arr, spacing=sp, order=1)

        def pick(p):
            p = p[np.isfinite(p)]
            if by == "Ra":
                value = float(np.mean(np.abs(p - p.mean())))
                row = next(r for r in PROFILE_CUTOFFS if value <= r[2])
                return row, f"Ra = {value:.4g} um"
            value = mean_width(p, sp[0], level=True)
            row = next(r for r in PROFILE_CUTOFFS if value <= r[3])
            return row, f"RSm = {value:.4g} um"

        row, why = pick(profile)
        notes.append(f"unfiltered {why} -> lambda_c {_fmt(row[0])} (ISO 4288)")
        if row[0] >= 2 * dmax and row[0] * 1.0 <= arr.size * sp[0]:
            row2, why2 = pick(l_filter(profile, sp, row[0]))
            if row2 != row:
                notes.append(f"with it, {why2} -> lambda_c {_fmt(row2[0])}")
                row = row2
        l_cut, s_cut = row[0], row[1]
        length = arr.size * sp[0]
        if l_cut > length:
            notes.append(f"profile ({_fmt(length)}) shorter than lambda_c: L-filter off")
            l_cut = None
        notes.append(f"lambda_s {_fmt(s_cut)} (ISO 3274)")
        if s_cut > length / 5:
            notes.append(f"lambda_s over a fifth of the profile ({_fmt(length)}): S-filter off")
            s_cut = None
    else:
        side = min(n * d for n, d in zip(arr.shape, sp))
        fits = [v for v in PREFERRED_NESTING_INDICES if v <= side / 5 and v >= 2 * dmax]
        l_cut = max(fits) if fits else None
        notes.append(f"L {_fmt(l_cut)}: largest preferred <= shorter side / 5 = {_fmt(side / 5)}"
                     if l_cut else "field too small for an L-filter (side / 5 < 2 spacings)")
        partner = next((r[1] for r in PROFILE_CUTOFFS if l_cut and l_cut <= r[0]), 0.0)
        s_cut = min((v for v in PREFERRED_NESTING_INDICES if v >= max(3 * dmax, partner)),
                    default=None)
        notes.append(f"S {_fmt(s_cut)}: smallest preferred >= 3 spacings ({_fmt(3 * dmax)})"
                     + (f" and >= {_fmt(partner)}" if partner else "") if s_cut is not None
                     else f"no S-filter: 3 spacings ({_fmt(3 * dmax)}) exceed the largest "
                          f"preferred nesting index ({_fmt(PREFERRED_NESTING_INDICES[-1])})")
    if s_cut is not None and (s_cut < 2 * dmax or (l_cut is not None and s_cut > l_cut / 3)):
        notes.append("S-filter off (below 2 spacings or not below L / 3)")
        s_cut = None
    return Cutoffs(s_cut, l_cut, "; ".join(notes))


def _reason_for(reason, s_auto, l_auto):
    """The notes of :func:`default_cutoffs` about the cut-offs that were chosen automatically
    (an L given by the caller is not explained by the default it replaced)."""
    about_s = ("S ", "S-filter", "lambda_s")
    kept = [part for part in reason.split("; ")
            if (s_auto if part.startswith(about_s) else l_auto)]
    given = [name for name, auto in (("S", s_auto), ("L", l_auto)) if not auto]
    return "; ".join(kept + ([f"{' and '.join(given)} set by the caller"] if given else []))


# --------------------------------------------------------------------------- the chain

@dataclass(frozen=True)
class Texture:
    """The result of :func:`surface_texture` (arrays of the shape of ``z``; NaN kept).

    Attributes:
        primary: the S-filtered surface with its form (ISO 25178-2's primary surface).
        sf: the S-F surface (form removed, short wavelengths removed).
        waviness: the L-filter's long-wavelength part of ``sf``.
        sl: the S-L surface ``sf - waviness`` (roughness).
        form: the F-operator's :class:`~roughgp.metrology.form.FormFit`.
        cutoffs: the :class:`Cutoffs` used.
        operators: the operators applied, e.g. ``["F: plane", "S: Gaussian 2.5 um",
            "L: Gaussian 0.8 mm"]``.
    """

    primary: np.ndarray
    sf: np.ndarray
    waviness: np.ndarray
    sl: np.ndarray
    form: FormFit
    cutoffs: Cutoffs
    operators: list = field(default_factory=list)


def surface_texture(z, spacing=1.0, *, form="plane", s="auto", l="auto", degree=2,
                    axis="auto", edge="normalised", mean_line=None, mean_line_label="Gaussian"):
    """F-operator, S-filter and L-filter in one call.

    The form (``"plane"``, ``"polynomial"`` of ``degree``, ``"cylinder"`` along ``axis``, or
    None) is fitted to the raw heights and subtracted first, then the S-filter (nesting
    index ``s``) and the L-filter (``l``) act on the residual -- for a linear filter the
    same as S before F in the interior, without the border bias of smoothing a tilted or
    curved form. ``s`` / ``l``: a length, ``"auto"`` (:func:`default_cutoffs`) or None (off).
    ``mean_line``: the L-filter's long-wavelength part, a function ``(z, spacing, cutoff)``
    (default: :func:`gaussian_filter`; the robust regression filter of
    :mod:`roughgp.metrology.robust_filters` or ISO 13565-1's of
    :mod:`roughgp.metrology.stratified`), named ``mean_line_label`` in the operators.
    """
    arr = height_map(z)
    _, sp = normalize(arr.shape, spacing)
    auto = default_cutoffs(arr, sp) if "auto" in (s, l) else None
    s_cut = auto.s if isinstance(s, str) and s == "auto" else s
    l_cut = auto.l if isinstance(l, str) and l == "auto" else l
    if s_cut is not None:
        s_cut = check_cutoff("s", s_cut, sp)
    if l_cut is not None:
        l_cut = check_cutoff("l", l_cut, sp)
    if s_cut is not None and l_cut is not None and s_cut >= l_cut:
        raise ValueError(f"s must be smaller than l, got s={s_cut:g}, l={l_cut:g}")
    residual, fit = remove_form(arr, sp, form, degree=degree, axis=axis)
    form_part = arr - residual
    operators = [fit.label]
    sf = residual
    if s_cut is not None:
        sf = gaussian_filter(residual, sp, s_cut, edge=edge)
        operators.append(f"S: Gaussian {_fmt(s_cut)}")
    if l_cut is not None:
        waviness = (gaussian_filter(sf, sp, l_cut, edge=edge) if mean_line is None
                    else mean_line(sf, sp, l_cut))
        operators.append(f"L: {mean_line_label} {_fmt(l_cut)}")
    else:
        waviness = np.where(np.isfinite(sf), 0.0, np.nan)
    reason = ("set by the caller" if auto is None else
              _reason_for(auto.reason, s == "auto", l == "auto"))
    return Texture(sf + form_part, sf, waviness, sf - waviness, fit,
                   Cutoffs(s_cut, l_cut, reason), operators)
