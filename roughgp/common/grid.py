"""Regular grids: the layout convention shared by every module of roughgp.

* A profile is a 1-D array ``z[ix]``; a surface is a 2-D array ``z[iy, ix]`` (rows are y),
  the layout of images, ``matplotlib.pyplot.imshow`` and the x3p format.
* ``shape`` and ``spacing`` are given in array order: ``(ny, nx)`` and ``(dy, dx)``
  (a scalar spacing applies to every axis).
* Points, lags and frequencies carry their components in coordinate order on a trailing
  axis: ``(x,)`` for a profile, ``(x, y)`` for a surface. So ``points[iy, ix] = (x, y)``.
"""

from __future__ import annotations

import numpy as np

from roughgp.common.checks import check_positive

__all__ = ["normalize", "coordinates", "centred_lags", "centred_frequencies"]


def normalize(shape, spacing=1.0):
    """Validate ``shape`` (1-D or 2-D, positive integers) and broadcast ``spacing`` to it.

    Returns ``(shape, spacing)`` as a tuple of ints and a float64 array, both in array order.
    """
    shape = (shape,) if np.ndim(shape) == 0 else tuple(shape)
    if len(shape) not in (1, 2) or not all(isinstance(n, (int, np.integer)) and n >= 1
                                           for n in shape):
        raise ValueError(f"shape must be (n,) or (ny, nx) with positive integers, got {shape!r}")
    shape = tuple(int(n) for n in shape)
    try:
        spacing = np.broadcast_to(np.asarray(spacing, dtype=np.float64), (len(shape),)).copy()
    except ValueError:
        raise ValueError(f"spacing must be a scalar or one value per axis of shape {shape}, "
                         f"got {spacing!r}") from None
    check_positive("spacing", spacing)
    return shape, spacing


def _points(axes):
    """Stack per-axis values (array order) into points with components in (x, y) order."""
    mesh = np.meshgrid(*axes, indexing="ij")
    return np.stack(mesh[::-1], axis=-1)


def coordinates(shape, spacing=1.0):
    """Grid positions of shape ``(*shape, D)``: ``points[iy, ix] = (ix * dx, iy * dy)``."""
    shape, spacing = normalize(shape, spacing)
    return _points([np.arange(n) * d for n, d in zip(shape, spacing)])


def centred_lags(shape, spacing=1.0):
    """Lags of shape ``(*shape, D)`` with lag zero at index ``n // 2`` of each axis
    (``numpy.fft.fftshift`` order): ``(k - n // 2) * spacing`` per axis."""
    shape, spacing = normalize(shape, spacing)
    return _points([(np.arange(n) - n // 2) * d for n, d in zip(shape, spacing)])


def centred_frequencies(shape, spacing=1.0):
    """Frequencies (cycles per unit length) of shape ``(*shape, D)`` that pair with
    :func:`centred_lags` under the FFT: ``fftshift(fftfreq(n, spacing))`` per axis."""
    shape, spacing = normalize(shape, spacing)
    return _points([np.fft.fftshift(np.fft.fftfreq(n, d)) for n, d in zip(shape, spacing)])
