"""The holes of a map: each missing point's depth (its distance to the nearest measured point),
the holes as connected sets with their largest depth, and the depth classes that the fill's
band is calibrated by (:mod:`roughgp.filling.hole_band`, :mod:`roughgp.filling.local_scale`)."""

from __future__ import annotations

import numpy as np
import scipy.ndimage

__all__ = ["DEPTH_EDGES", "hole_depth", "depth_class", "hole_class"]

#: the depth classes' edges in points: classes [1, 2), [2, 4), ... [64, inf)
DEPTH_EDGES = (1.0, 2.0, 4.0, 8.0, 16.0, 32.0, 64.0)


def hole_depth(missing) -> np.ndarray:
    """The depth of each missing point: its distance in points to the nearest measured one
    (0 at measured points)."""
    missing = np.asarray(missing, dtype=bool)
    if missing.all():
        raise ValueError("missing marks every point: no measured point to measure depth from")
    return scipy.ndimage.distance_transform_edt(missing)


def depth_class(depth) -> np.ndarray:
    """The index of each depth's class in :data:`DEPTH_EDGES` (-1 for depth < 1: measured)."""
    return np.searchsorted(np.asarray(DEPTH_EDGES), np.asarray(depth, dtype=float),
                           side="right") - 1


def hole_class(missing, depth=None) -> tuple[np.ndarray, np.ndarray]:
    """The holes (connected missing points, 8-neighbours): ``(labels, deepest)``, with
    ``labels`` the map of hole numbers (0: measured) and ``deepest[k - 1]`` the largest depth of
    hole ``k``. A hole's width across is about ``2 deepest`` points."""
    missing = np.asarray(missing, dtype=bool)
    depth = hole_depth(missing) if depth is None else depth
    labels, n = scipy.ndimage.label(missing, structure=np.ones((3, 3)))
    if n == 0:
        return labels, np.zeros(0)
    deepest = scipy.ndimage.maximum(depth, labels, index=np.arange(1, n + 1))
    return labels, np.asarray(deepest, dtype=float)
