"""ISO texture parameters of a measurement after its F-operator, S- and L-filters.

:func:`filtered_parameters` runs the chain of :func:`roughgp.metrology.filters.surface_texture`
(form removed, S- and L-filter with the standard's default nesting indices unless given) and
computes the parameters of the resulting SL surface or roughness profile, as ISO 25178-3 and
ISO 4288 describe: ISO 25178-2 areal parameters (:func:`roughgp.metrology.texture.areal_parameters`)
or ISO 4287 / 13565-2 profile parameters. Unmeasured (NaN) points are left out of the point
statistics (height and material-ratio parameters); the parameters that need a complete grid
(Sal, Str, Std; RSm) are then NaN, with a note saying why.

Memory: the chain and the parameters need about :data:`BYTES_PER_POINT` bytes a point at their
peak (the FFTs of the filters and of the autocorrelation), so a map of more than
:data:`MAX_TEXTURE_POINTS` points, or one whose budget exceeds the free memory, is refused
with a ``ValueError`` before any of it is computed.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from roughgp.common.checks import constant_variance
from roughgp.common.memory import host_free_bytes
from roughgp.metrology import texture, texture_heights
from roughgp.metrology.filters import Texture, surface_texture
from roughgp.metrology.robust_filters import robust_gaussian_filter
from roughgp.metrology.stratified import stratified_mean_line

__all__ = ["L_FILTERS", "MAX_TEXTURE_POINTS", "BYTES_PER_POINT", "check_texture_size", "TextureReport",
           "filtered_parameters", "point_statistics", "UNITS", "unit_of"]

#: Units of the parameters that are not heights or lengths in µm.
UNITS = {"Ssk": "", "Sku": "", "Rsk": "", "Rku": "", "Str": "", "Std": "deg",
         "Smr1": "%", "Smr2": "%", "Mr1": "%", "Mr2": "%"}

_AREAL_FROM_PROFILE = {"Ra": "Sa", "Rq": "Sq", "Rp": "Sp", "Rv": "Sv", "Rt": "Sz",
                       "Rsk": "Ssk", "Rku": "Sku", "Rk": "Sk", "Rpk": "Spk", "Rvk": "Svk",
                       "Mr1": "Smr1", "Mr2": "Smr2"}


#: The L-filters: name -> (the mean line, its label in the operators, a note on it).
L_FILTERS = {
    "gaussian": (None, "Gaussian", None),
    "robust": (robust_gaussian_filter, "robust Gaussian regression (ISO 16610-31 / -71, order 2)",
               "robust L-filter: the mean line does not follow spikes, pits or deep valleys"),
    "stratified": (stratified_mean_line, "ISO 13565-1 (valleys suppressed, two Gaussian passes)",
                   "ISO 13565-1 filter for stratified surfaces: its Sk / Spk / Svk (Rk / Rpk / "
                   "Rvk) are the standard's; the other parameters are of the same surface"),
}

#: Largest map whose parameters are computed: 2**24 points (4096 x 4096, about 6 GiB at the peak).
MAX_TEXTURE_POINTS = 2 ** 24
#: Peak memory of :func:`filtered_parameters` per point of the map (measured: 310-400 bytes).
BYTES_PER_POINT = 400


def check_texture_size(shape) -> None:
    """Raise a ``ValueError`` naming the size and the limit when the parameters of a map of
    ``shape`` would need more than :data:`MAX_TEXTURE_POINTS` points or 80 % of the free memory."""
    points = math.prod(shape)
    needed = BYTES_PER_POINT * points
    size = " x ".join(map(str, shape))
    if points > MAX_TEXTURE_POINTS:
        raise ValueError(f"a map of {size} = {points} points is too large for the texture "
                         f"parameters (at most MAX_TEXTURE_POINTS = {MAX_TEXTURE_POINTS} points; "
                         f"they would need about {needed / 2**30:.1f} GiB): crop or subsample it")
    free = host_free_bytes()
    if needed > 0.8 * free:
        raise ValueError(f"the texture parameters of a map of {size} points need about "
                         f"{needed / 2**30:.1f} GiB, but only {free / 2**30:.1f} GiB of memory "
                         f"are free: crop or subsample it")


def unit_of(name: str) -> str:
    """The unit of a texture parameter: µm (``"um"``) unless listed in :data:`UNITS`."""
    return UNITS.get(name, "um")


@dataclasses.dataclass
class TextureReport:
    """What :func:`filtered_parameters` returns.

    Attributes:
        parameters: ISO symbol -> value (NaN where undefined).
        standard: which parameter set (areal or profile) and of which surface.
        operators: the operators applied, e.g. ``["F: plane", "S: Gaussian 2.5 um",
            "L: Gaussian 80 um"]`` (empty without filtering).
        notes: why a parameter is NaN, how the cut-offs were chosen.
        texture: the chain's :class:`~roughgp.metrology.filters.Texture` (None unfiltered).
        heights: the heights the parameters were computed on.
    """

    parameters: dict
    standard: str
    operators: list
    notes: list
    texture: Texture | None
    heights: np.ndarray


def point_statistics(h, areal):
    """Height and material-ratio parameters of the measured points of ``h`` alone."""
    values = h[np.isfinite(h)]
    out = texture_heights.height_parameters(values, undefined="nan")
    out.update(texture_heights.material_ratio_parameters(values, undefined="nan"))
    if not areal:
        return out
    return {_AREAL_FROM_PROFILE[k]: v for k, v in out.items()}


def filtered_parameters(z, spacing=1.0, *, form="plane", s="auto", l="auto", degree=2,
                        axis="auto", filtered=True, l_kind="gaussian") -> TextureReport:
    """ISO parameters of ``z`` (profile ``z[ix]`` or surface ``z[iy, ix]``, µm) after its
    F-operator and S-/L-filters (module docstring).

    Args:
        spacing: scalar or ``(dy, dx)``.
        form: ``"plane"`` (a line for a profile), ``"polynomial"`` (of ``degree``),
            ``"cylinder"`` (along ``axis``: ``"x"``, ``"y"``, ``"auto"``) or None.
        s, l: nesting indices in µm, ``"auto"`` (the standard's defaults) or None (off).
        filtered: False: no F-, S- or L-operator at all: the heights referred to their mean
            (the parameters of the primary surface "as measured").
        l_kind: the L-filter (:data:`L_FILTERS`): ``"gaussian"`` (ISO 16610-21 / -61),
            ``"robust"`` (ISO 16610-31 / -71) or ``"stratified"`` (ISO 13565-1, for Sk / Rk).
    """
    if l_kind not in L_FILTERS:
        raise ValueError(f"l_kind must be one of {', '.join(L_FILTERS)}, got {l_kind!r}")
    z = np.asarray(z, dtype=np.float64)
    check_texture_size(z.shape)
    areal = z.ndim == 2
    notes = []
    if filtered:
        mean_line, label, note = L_FILTERS[l_kind]
        chain = surface_texture(z, spacing, form=form, s=s, l=l, degree=degree, axis=axis,
                                mean_line=mean_line, mean_line_label=label)
        if note and chain.cutoffs.l is not None:
            notes.append(note)
        heights, operators = chain.sl, list(chain.operators)
        if chain.cutoffs.reason:
            notes.append(chain.cutoffs.reason)
        what = ("SL surface" if chain.cutoffs.l is not None else "SF surface") if areal else \
            ("roughness profile" if chain.cutoffs.l is not None else "primary profile, form removed")
    else:
        chain, heights, operators = None, z, []
        what = "unfiltered heights, referred to their mean"
    standard = (f"ISO 25178-2 areal parameters of the {what}" if areal else
                f"ISO 4287 / ISO 13565-2 profile parameters of the {what}")
    rounding = constant_variance(heights, z) if filtered else None
    if rounding is not None and rounding > 0:  # a flat map: Sku 16 of the operators' rounding
        heights = np.where(np.isfinite(heights), 0.0, heights)
        notes.append(f"the heights after the operators are constant (variance {rounding:.3g} "
                     f"um^2, the operators' rounding): the parameters of a flat surface (the "
                     f"heights 0; the shape parameters undefined, nan)")
    missing = int(np.count_nonzero(~np.isfinite(heights)))
    if missing == 0:
        params = (texture.areal_parameters(heights, spacing=spacing, undefined="nan") if areal
                  else texture.profile_parameters(heights, spacing=float(np.ravel(spacing)[-1]),
                                                  undefined="nan"))
    else:
        params = point_statistics(heights, areal)
        grid_only = ("Sal", "Str", "Std") if areal else ("RSm",)
        params.update(dict.fromkeys(grid_only, float("nan")))
        notes.append(f"{missing} of {heights.size} points unmeasured ({missing / heights.size:.1%}):"
                     f" the height and material-ratio parameters are of the measured points; "
                     f"{', '.join(grid_only)} need{'s' if len(grid_only) == 1 else ''} a "
                     f"complete grid (fill it: roughgp fill)")
    return TextureReport(params, standard, operators, notes, chain, heights)
