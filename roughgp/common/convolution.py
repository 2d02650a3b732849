"""Convolution along one axis by FFT (``scipy.fft``), as ``scipy.signal.fftconvolve(a, k,
mode="same", axes=axis)`` computes it.

The filters of :mod:`roughgp.metrology` need only this one function of ``scipy.signal``,
whose package import costs 0.5-0.8 s on the 2-core machine (it imports ``scipy.stats`` and
``scipy.interpolate``): a person notices it on every ``roughgp texture``. ``scipy.fft`` alone
is a tenth of that. ``tests/common/test_convolution.py`` compares the two.
"""

from __future__ import annotations

import numpy as np
from scipy import fft

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
    size = fft.next_fast_len(full, real=True)
    shape = [1] * a.ndim
    shape[axis] = -1
    spectrum = fft.rfft(a, size, axis=axis) * fft.rfft(kernel, size).reshape(shape)
    start = (kernel.size - 1) // 2
    return np.take(fft.irfft(spectrum, size, axis=axis), np.arange(start, start + n), axis=axis)
