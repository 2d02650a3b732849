"""Convolution along one axis by FFT (``numpy.fft``), as ``scipy.signal.fftconvolve(a, k,
mode="same", axes=axis)`` computes it.

The filters of :mod:`roughgp.metrology` need only this one function of ``scipy.signal``,
whose package import costs 0.5-0.8 s on the 2-core machine (it imports ``scipy.stats`` and
``scipy.interpolate``): a person notices it on every ``roughgp texture``. ``scipy.fft`` costs
0.3-0.5 s more (its import pulls ``scipy.special`` and SciPy's array-API layer, which parses
docstrings), where ``numpy.fft`` (the same pocketfft) comes with numpy.
``tests/common/test_convolution.py`` compares the result with ``scipy.signal``'s.
"""

from __future__ import annotations

import numpy as np

__all__ = ["convolve_same"]


def convolve_same(a, kernel, axis: int = -1) -> np.ndarray:
    """The linear convolution of the real array ``a`` with the real 1-D ``kernel`` along
    ``axis``, the part of the size of ``a`` centred in the full convolution (as
    ``scipy.signal.fftconvolve(..., mode="same")``: the full result from index
    ``(kernel.size - 1) // 2`` on).
    """
    a = np.asarray(a, dtype=np.float64)
    kernel = np.asarray(kernel, dtype=np.float64).ravel()
    axis = axis % a.ndim
    n = a.shape[axis]
    full = n + kernel.size - 1
    size = _fast_length(full)
    shape = [1] * a.ndim
    shape[axis] = -1
    spectrum = np.fft.rfft(a, size, axis=axis) * np.fft.rfft(kernel, size).reshape(shape)
    start = (kernel.size - 1) // 2
    return np.take(np.fft.irfft(spectrum, size, axis=axis), np.arange(start, start + n),
                   axis=axis)


def _fast_length(n: int) -> int:
    """The smallest 5-smooth length (2^a 3^b 5^c) of at least ``n``: an FFT length pocketfft
    transforms fast (``scipy.fft.next_fast_len`` without importing ``scipy.fft``)."""
    best = 1 << max(n - 1, 0).bit_length()  # the next power of two
    power5 = 1
    while power5 < best:
        power35 = power5
        while power35 < best:
            length = power35 << max(-(-n // power35) - 1, 0).bit_length()  # times a power of 2
            best = min(best, length)
            power35 *= 3
        power5 *= 5
    return best
