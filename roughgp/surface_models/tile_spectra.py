r"""The spectrum's shape of a draw of tiles, relative to all the tiles (beyond the paper; issue
40, items 2 and 3).

The tile bootstrap (:mod:`roughgp.checking.tile_bootstrap`) gives each predictive model the
variance and the heights of tiles of the fitted map drawn with replacement. Its spectrum's
shape was the fit's: every simulation had the fitted crop's correlation lengths, lay and
direction, so the check's Sal, Str and Std of another crop of the same part were ranked among
draws as alike as the fit's point estimate makes them.

Here each tile's prewhitened periodogram (:func:`~roughgp.surface_models.psd_table.periodogram`,
the ordinates at which the table's log-polar bins are made) is pooled in coarse log-polar bins
(:data:`RINGS` rings over the model's band, :data:`ANGLES` directions over 180 degrees): one
of the bootstrap's 4 x 4 tiles is a quarter of the map along each side, so its ordinates lie
four times further apart than the map's and a coarse bin holds as many of them as
:data:`MIN_ORDINATES` needs. For a
draw of tiles, :func:`shape_factor` is the drawn tiles' mean ordinate per bin over all the
tiles' (1 where the drawn tiles hold fewer than :data:`MIN_ORDINATES` ordinates in a bin, as
below the tiles' own fundamental frequency), spread over the model's finer table
(:data:`~roughgp.surface_models.psd_table.N_RADII` x
:data:`~roughgp.surface_models.psd_table.N_ANGLES`). On a stationary surface its spread is the
sampling spread of the map's spectrum at the tiles' resolution (the mean over 16 resampled
tiles of what the map's bins average); on a part that varies, the variation of the spectrum's
shape between its regions as far as the fitted map shows it.
"""

from __future__ import annotations

import math

import numpy as np

from roughgp.surface_models import psd_table

__all__ = ["RINGS", "ANGLES", "MIN_ORDINATES", "tile_ordinates", "shape_factor"]

RINGS = 8          #: coarse logarithmic rings over the model's band (5 of the table's each)
ANGLES = 12        #: coarse directions over 180 degrees (15 degrees, 3 of the table's each)
MIN_ORDINATES = 32  #: the fewest pooled ordinates of the drawn tiles a bin's factor needs


def tile_ordinates(tiles, spacing, f_min, f_max) -> tuple[np.ndarray, np.ndarray]:
    """``(sums, counts)``, each ``(len(tiles), RINGS, ANGLES)``: per tile (heights, um, NaN
    where unmeasured) the sum and the number of its prewhitened periodogram's ordinates in
    each coarse bin of the band ``[f_min, f_max]`` (1/um); ordinates outside the band, at
    zero frequency or not finite are left out, and so is a tile whose periodogram has no
    data (fewer than 16 measured points, or none inside its window): its counts are 0."""
    if not 0 < f_min < f_max:
        raise ValueError(f"f_min and f_max must satisfy 0 < f_min < f_max, got {f_min}, {f_max}")
    sums = np.zeros((len(tiles), RINGS, ANGLES))
    counts = np.zeros((len(tiles), RINGS, ANGLES))
    step = math.log(f_max / f_min) / RINGS
    for k, tile in enumerate(tiles):
        try:
            qy, qx, c = psd_table.periodogram(tile, spacing)
        except ValueError:   # a tile all but unmeasured (psd_table says why): no ordinates
            continue
        r, theta = psd_table.polar(qy, qx)
        keep = (r >= f_min * (1 - 1e-9)) & (r <= f_max * (1 + 1e-9)) & np.isfinite(c)
        ring = np.clip(((np.log(r[keep]) - math.log(f_min)) / step).astype(int), 0, RINGS - 1)
        angle = np.clip((theta[keep] / (math.pi / ANGLES)).astype(int), 0, ANGLES - 1)
        flat = ring * ANGLES + angle
        sums[k] = np.bincount(flat, weights=c[keep], minlength=RINGS * ANGLES).reshape(
            RINGS, ANGLES)
        counts[k] = np.bincount(flat, minlength=RINGS * ANGLES).reshape(RINGS, ANGLES)
    return sums, counts


def shape_factor(sums, counts, pick) -> np.ndarray:
    """The factor ``(N_RADII, N_ANGLES)`` on a measured-psd model's table for the tiles
    ``pick`` (indices, repeats allowed) of :func:`tile_ordinates`: per coarse bin the picked
    tiles' mean ordinate over all the tiles', 1 where the picked tiles hold fewer than
    :data:`MIN_ORDINATES` ordinates or the mean of all is not > 0 (module docstring). The
    variance is the caller's to set: the factor changes the spectrum's shape and level."""
    pick = np.asarray(pick, dtype=int)
    picked_sum, picked_count = sums[pick].sum(axis=0), counts[pick].sum(axis=0)
    all_sum, all_count = sums.sum(axis=0), counts.sum(axis=0)
    with np.errstate(invalid="ignore", divide="ignore"):
        whole = all_sum / all_count
        coarse = (picked_sum / picked_count) / whole
    usable = (picked_count >= MIN_ORDINATES) & (whole > 0) & np.isfinite(coarse) & (coarse > 0)
    coarse = np.where(usable, coarse, 1.0)
    rows = np.arange(psd_table.N_RADII) * RINGS // psd_table.N_RADII
    cols = np.arange(psd_table.N_ANGLES) * ANGLES // psd_table.N_ANGLES
    return coarse[np.ix_(rows, cols)]
