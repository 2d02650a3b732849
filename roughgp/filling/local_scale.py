r"""The local roughness around each hole: the scale that makes the fill's band adapt to the map.

The GP's predictive sd depends on where the data are, not on what the surface does there: one
stationary covariance is fitted to the whole map. Where the texture changes across the map (the
steep flank of a land, a worn zone, a defect) the errors in a hole there are many times the
sd, and one factor per size of hole (:mod:`roughgp.filling.hole_band`), calibrated on copies at
random places, must either miss them or widen the band everywhere. On sample-land's central
256 x 256 points, whose last 40 rows are the land's flank, holes there erred by 5 to 24 sd and
the band held 86 % of the heights in holes 21 to 40 points across.

:func:`local_scale` measures the roughness around each hole from the measured points near it:

.. math:: \ell = \sqrt{\overline{\Delta z^2}_{\text{around the hole}} \big/
          \overline{\Delta z^2}_{\text{map}}},

the mean squared difference of measured neighbours (along x and y) in a window that reaches
past the hole (half-width :data:`RING` points more than the largest depth of the hole's class),
over that of the whole map (shrunk toward 1 by :data:`PRIOR_PAIRS`). The band's scores are
divided by it where the band is calibrated and multiplied by it where it is used (a
normalised, locally weighted split-conformal band: Lei, G'Sell, Rinaldo, Tibshirani &
Wasserman, "Distribution-free predictive inference for regression", JASA 2018): the
calibration stays valid for any such scale computed alike on the copies and on the holes, and
a scale that follows the errors makes the band narrower where the map is smooth and wider
where it is rough.
"""

from __future__ import annotations

import numpy as np
import scipy.ndimage

from roughgp.filling.hole_geometry import DEPTH_EDGES, depth_class, hole_class

__all__ = ["RING", "PRIOR_PAIRS", "local_scale"]

#: the window reaches this many points beyond the largest depth of a hole's class
RING = 4
#: the local mean square is shrunk toward the map's as if this many more pairs had it (a
#: window with hundreds of pairs barely moves; a flat or nearly empty one keeps a scale > 0)
PRIOR_PAIRS = 8


def local_scale(residual, missing, depth=None) -> np.ndarray:
    """:math:`\\ell` at each point of ``missing`` (1 elsewhere): the local roughness around its
    hole over the map's (module docstring).

    Args:
        residual: form-removed heights; NaN (and ``missing``) points are not measured.
        missing: boolean map of the points to score or fill (their holes: connected sets).
        depth: ``hole_depth(missing)`` where the caller has it already (else computed).
    """
    residual = np.asarray(residual, dtype=np.float64)
    missing = np.asarray(missing, dtype=bool)
    if residual.shape != missing.shape:
        raise ValueError(f"missing must have the shape of residual {residual.shape}, got "
                         f"{missing.shape}")
    out = np.ones(residual.shape)
    measured = np.isfinite(residual) & ~missing
    if not missing.any() or residual.ndim != 2 or min(residual.shape) < 2:
        return out
    z = np.where(measured, residual, 0.0)
    squares, counts = np.zeros(z.shape), np.zeros(z.shape)
    for a, b in (((slice(0, -1), slice(None)), (slice(1, None), slice(None))),
                 ((slice(None), slice(0, -1)), (slice(None), slice(1, None)))):
        pair = measured[a] & measured[b]          # neighbours along y, then along x
        d2 = np.where(pair, (z[b] - z[a]) ** 2, 0.0)
        for end in (a, b):                        # a pair counts at both its points
            squares[end] += d2
            counts[end] += pair
    if counts.sum() == 0 or squares.sum() == 0:
        return out
    overall = squares.sum() / counts.sum()
    labels, deepest = hole_class(missing, depth)
    classes = np.concatenate([[-1], depth_class(deepest)])[labels]
    for c in np.unique(classes[missing]):
        reach = DEPTH_EDGES[c + 1] if c + 1 < len(DEPTH_EDGES) else 2 * DEPTH_EDGES[c]
        size = 2 * int(reach + RING) + 1
        points = classes == c
        area = size * size   # uniform_filter gives window means: back to sums
        local_sum = area * scipy.ndimage.uniform_filter(squares, size, mode="constant")[points]
        local_count = area * scipy.ndimage.uniform_filter(counts, size, mode="constant")[points]
        # PRIOR_PAIRS pairs at the map's mean: never 0 where a window is flat or nearly empty
        out[points] = np.sqrt((np.maximum(local_sum, 0.0) + PRIOR_PAIRS * overall)
                              / (np.maximum(local_count, 0.0) + PRIOR_PAIRS) / overall)
    return out
