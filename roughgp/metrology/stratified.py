r"""The filter for surfaces with stratified functional properties (ISO 13565-1:1996).

A plateau-honed surface (the paper's figure 3, eq 19-20) is a smooth plateau cut by deep
valleys. The plain Gaussian mean line (ISO 16610-21) is pulled down into the valleys, so
the roughness profile's plateau rises above zero and the valleys look shallower: the core
and peak parameters Rk, Rpk (Sk, Spk) that the material-ratio curve of ISO 13565-2 is
meant to read come out distorted. ISO 13565-1 suppresses the valleys in two passes:

1. the Gaussian mean line :math:`w_1` of the primary profile (ISO 16610-21, cut-off
   :math:`\lambda_c`, 0.8 or 2.5 mm in the standard);
2. the profile with its valleys suppressed, :math:`\max(z, w_1)` (the points below the first
   mean line replaced by it);
3. the Gaussian mean line :math:`w_2` of that profile: the reference line;
4. the roughness profile :math:`z - w_2` of the *unmodified* profile.

On a surface the same two passes use the areal Gaussian filter (ISO 16610-61). The standard
says nothing of holes: NaN points take no weight in either pass (the NaN-aware filter of
:mod:`roughgp.metrology.filters`) and stay NaN. Its ends are those of the Gaussian filter
(zeroth-order correction); the standard itself asks for a profile one cut-off longer than the
evaluation length, i.e. half a cut-off dropped at each end (``edge="drop"``).
"""

from __future__ import annotations

import numpy as np

from roughgp.common.checks import height_map
from roughgp.metrology.filters import gaussian_filter

__all__ = ["stratified_mean_line", "stratified_l_filter"]


def stratified_mean_line(z, spacing, cutoff, *, edge="normalised"):
    """The ISO 13565-1 reference line (profile ``z[ix]``) or surface (``z[iy, ix]``): the
    Gaussian mean line of ``z`` with its valleys below a first Gaussian mean line suppressed
    (module docstring). ``cutoff`` and ``edge`` as in
    :func:`roughgp.metrology.filters.gaussian_filter`; NaN stays NaN."""
    arr = height_map(z)
    first = gaussian_filter(arr, spacing, cutoff, edge="normalised")
    suppressed = np.where(arr < first, first, arr)  # NaN (either) stays NaN
    return gaussian_filter(suppressed, spacing, cutoff, edge=edge)


def stratified_l_filter(z, spacing, cutoff, *, edge="normalised"):
    """The ISO 13565-1 roughness profile / SL surface: ``z`` minus its
    :func:`stratified_mean_line`."""
    arr = height_map(z)
    return arr - stratified_mean_line(arr, spacing, cutoff, edge=edge)
