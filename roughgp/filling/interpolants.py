"""Classical interpolation of missing points: the baseline a GP fill must beat (beyond the paper).

:func:`interpolate_baseline` is what ``scipy.interpolate.griddata`` does, nearest neighbour,
linear on the Delaunay triangulation and cubic (Clough-Tocher), with one triangulation for
linear and cubic, restricted to a window of the grid plus a margin (a Delaunay triangulation of
a whole regular grid is slow); :func:`interpolate_holes` does it per hole, for small scattered
holes (one small triangulation each). The chapters "Filling unmeasured points" and "Measured
surfaces" and the fill's self-check (:mod:`roughgp.filling.self_check`) compare the GP
with it.
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np
import scipy.interpolate
import scipy.ndimage
import scipy.spatial

from roughgp.common.threads import single_blas_thread

__all__ = ["INTERPOLANTS", "Baseline", "interpolate_baseline", "interpolate_holes"]

INTERPOLANTS = ("nearest", "linear", "cubic")


@dataclass(frozen=True)
class Baseline:
    """Classical interpolation of the missing points of a window (:func:`interpolate_baseline`).

    Attributes:
        evaluate: boolean map of the points scored (missing and inside the window).
        values: ``{method: heights at the evaluate points}`` for :data:`INTERPOLANTS`.
        seconds: ``{method: wall time}`` (the triangulation not included).
        delaunay_seconds: wall time of the Delaunay triangulation (shared by linear and cubic).
        n_window: points in the window.
        margin: the margin used: the one asked for, or wider where the window and that margin
            held too few measured points for a triangulation (fewer than 3, or all on a line).
        nearest_only: True where even the whole grid could not be triangulated: every method
            then gives the nearest measured value.
    """

    evaluate: np.ndarray
    values: dict
    seconds: dict
    delaunay_seconds: float
    n_window: int
    margin: int = 0
    nearest_only: bool = False


def _interpolant(method, points, values, triangulation):
    if method == "nearest" or triangulation is None:
        return scipy.interpolate.NearestNDInterpolator(points, values)
    if method == "linear":
        return scipy.interpolate.LinearNDInterpolator(triangulation, values)
    return scipy.interpolate.CloughTocher2DInterpolator(triangulation, values)


def _neighbourhood(z, missing, window, margin):
    """The measured points (grid coordinates) and heights of ``window`` plus ``margin``, and
    the outer window's slices and indices."""
    rows, cols = window
    r0, c0 = max(rows.start - margin, 0), max(cols.start - margin, 0)
    outer = np.s_[r0:rows.stop + margin, c0:cols.stop + margin]
    # the work stays in the outer window (a hole's box, not the grid), in grid coordinates
    iy, ix = np.indices(z[outer].shape)
    iy, ix = iy + r0, ix + c0
    use = ~missing[outer]
    points = np.column_stack([iy[use], ix[use]]).astype(float)
    whole = z[outer].shape == z.shape
    return outer, iy, ix, points, z[outer][use], whole


@single_blas_thread
def interpolate_baseline(z, missing, window, *, margin=12,
                         methods=INTERPOLANTS) -> Baseline:
    """Nearest, linear and cubic interpolation (what ``scipy.interpolate.griddata`` does, with
    one triangulation for both) of the missing points inside ``window`` (a pair of slices),
    from the measured points of the window plus ``margin`` points around it. Points outside the
    convex hull get the nearest value. Where the window and its margin hold too few measured
    points to triangulate (fewer than 3, or all on a line: a hole at the edge of a map with
    large unmeasured regions), the margin is doubled until they do; where the whole grid does
    not, every method gives the nearest value (``Baseline.nearest_only``).
    ``methods``: a subset of :data:`INTERPOLANTS`."""
    unknown = set(methods) - set(INTERPOLANTS)
    if unknown or not methods:
        raise ValueError(f"methods must be a non-empty subset of {INTERPOLANTS}, got {methods!r}")
    delaunay_seconds = 0.0
    while True:
        outer, iy, ix, points, heights, whole = _neighbourhood(z, missing, window, margin)
        triangulation = None
        if len(points) >= 3:
            start = time.perf_counter()
            try:
                triangulation = scipy.spatial.Delaunay(points)
            except scipy.spatial.QhullError:  # all on a line
                triangulation = None
            delaunay_seconds += time.perf_counter() - start
        if triangulation is not None or whole:
            break
        margin = max(2 * margin, 1)
    if len(points) == 0:
        raise ValueError("z holds no measured point to interpolate from")
    evaluate = np.zeros(z.shape, dtype=bool)
    evaluate[window] = missing[window]
    here = evaluate[outer]
    targets = np.column_stack([iy[here], ix[here]]).astype(float)
    values, seconds = {}, {}
    for method in methods:
        start = time.perf_counter()
        got = _interpolant(method, points, heights, triangulation)(targets)
        outside = np.isnan(got)
        got[outside] = scipy.interpolate.NearestNDInterpolator(points, heights)(targets[outside])
        values[method] = got
        seconds[method] = time.perf_counter() - start
    return Baseline(evaluate, values, seconds, delaunay_seconds, int(evaluate[window].size),
                    margin, triangulation is None)


def interpolate_holes(z, holes, *, margin=6, methods=INTERPOLANTS, notes=None) -> dict:
    """``{method: heights at the points of holes}`` (in ``z[holes]``'s order): each connected
    hole of the boolean map ``holes`` interpolated from the measured points (finite and not in
    ``holes``) of its bounding box plus ``margin`` points around, by
    :func:`interpolate_baseline`. For small scattered holes this is far quicker than one
    triangulation of the grid, and it agrees with it but where a grid's cocircular points make
    Delaunay's choice of diagonal arbitrary. ``notes``: a list that receives one line when
    some holes needed a wider margin (too few measured neighbours) or the nearest value."""
    holes = np.asarray(holes, dtype=bool)
    missing = ~np.isfinite(z) | holes
    masked = np.where(missing, np.nan, z)
    out = {method: np.full(z.shape, np.nan) for method in methods}
    labels, _ = scipy.ndimage.label(holes)
    widened = nearest = 0
    for window in scipy.ndimage.find_objects(labels):
        base = interpolate_baseline(masked, missing, window, margin=margin, methods=methods)
        widened += base.margin > margin
        nearest += base.nearest_only
        for method in methods:
            out[method][base.evaluate] = base.values[method]
    if notes is not None and widened:
        notes.append(f"{widened} of {len(scipy.ndimage.find_objects(labels))} held-out discs "
                     f"had too few measured neighbours within {margin} points: interpolated "
                     "from a wider margin" + (f" ({nearest} from the nearest value alone)"
                                              if nearest else ""))
    return {method: values[holes] for method, values in out.items()}
