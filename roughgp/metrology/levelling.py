"""Levelling: removal of the mean, or of the least-squares line (profile) or plane (surface).

A measured profile ``z[ix]`` or surface ``z[iy, ix]`` carries the tilt of its mounting; the
texture is what is left after the least-squares line or plane is subtracted (the usual
F-operator of ISO 25178-2 / ISO 4287 when no form is removed). ``NaN`` marks a point that was
not measured: it takes no part in the fit and stays ``NaN`` in the result.

Coordinates are those of :mod:`roughgp.common.grid`: ``x = ix * dx`` and ``y = iy * dy`` with
``spacing`` in array order (``dx`` for a profile, ``(dy, dx)`` for a surface), so the fitted
plane is ``offset + slope_y * y + slope_x * x``; slopes are in height units per unit of
``spacing``.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from roughgp.common.checks import profile_or_surface
from roughgp.common.grid import normalize

__all__ = ["LevelFit", "level"]


class LevelFit(NamedTuple):
    """The fitted and removed polynomial: ``offset + sum(slope[k] * coordinate_k)``.

    ``offset`` is the fitted height at index 0 (``x = y = 0``); ``slope`` holds the
    slopes in array order, ``(dz/dx,)`` for a profile and ``(dz/dy, dz/dx)`` for a
    surface, and is empty for ``order=0`` (then ``offset`` is the mean).
    """

    offset: float
    slope: tuple[float, ...]


def level(z, *, spacing=1.0, order=1, return_coefficients=False):
    """Subtract the least-squares mean (``order=0``), line or plane (``order=1``).

    Args:
        z: a profile ``z[ix]`` (1-D) or a surface ``z[iy, ix]`` (2-D), any height unit;
            ``NaN`` marks missing points (ignored by the fit, kept in the result), infinite
            values are refused.
        spacing: scalar or one value per axis in array order (``(dy, dx)``), > 0; it only
            scales the reported slopes, the levelled heights do not depend on it.
        order: 0 (mean) or 1 (line / plane).
        return_coefficients: also return the removed fit as a :class:`LevelFit`.

    Returns:
        The levelled array (a new float64 array of the shape of ``z``), or
        ``(levelled, LevelFit)`` with ``return_coefficients=True``.

    Raises:
        ValueError: ``z`` not 1-D / 2-D, infinite values, too few measured points to
            determine the fit (e.g. all NaN, or a plane through points on one line),
            ``order`` not in {0, 1}, bad ``spacing``.
    """
    arr = profile_or_surface(z)  # a copy: the caller's array is never changed
    if isinstance(order, bool) or order not in (0, 1):
        raise ValueError(f"order must be 0 (mean) or 1 (line / plane), got {order!r}")
    _, spacing = normalize(arr.shape, spacing)

    measured = ~np.isnan(arr)
    n_coef = 1 + order * arr.ndim
    if np.count_nonzero(measured) < n_coef:
        raise ValueError(f"z has {np.count_nonzero(measured)} measured (non-NaN) points; "
                         f"order={order} needs at least {n_coef}")
    values = arr[measured]
    if order == 0:
        offset = float(values.mean())
        arr -= offset
        fit = LevelFit(offset, ())
    else:
        # Positions per axis in array order, centred on their mean for a well-conditioned
        # solve; the offset is moved back to index 0 afterwards.
        idx = np.nonzero(measured)
        coords = [i * d for i, d in zip(idx, spacing)]
        centres = [c.mean() for c in coords]
        design = np.column_stack([np.ones(values.size)]
                                 + [c - m for c, m in zip(coords, centres)])
        coef, _, rank, _ = np.linalg.lstsq(design, values, rcond=None)
        if rank < n_coef:
            raise ValueError("the measured (non-NaN) points of z do not determine a "
                             "plane (they lie on one line); use order=0 or level rows / "
                             "columns as profiles")
        slope = coef[1:]
        offset = float(coef[0] - np.dot(slope, centres))
        axes = np.meshgrid(*[np.arange(n) * d for n, d in zip(arr.shape, spacing)],
                           indexing="ij", sparse=True)
        arr -= offset + sum(s * a for s, a in zip(slope, axes))
        fit = LevelFit(offset, tuple(float(s) for s in slope))
    return (arr, fit) if return_coefficients else arr
