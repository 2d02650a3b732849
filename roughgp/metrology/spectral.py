r"""Estimates of the ACVF and the PSD from one sampled profile or surface.

All estimates use the two-sided PSD of eq 5 (so that :math:`\int S\,df` is the variance) and
the grid conventions of :mod:`roughgp.common.grid`. For data sampled at spacing :math:`\Delta` the
target of a PSD estimate is the *aliased* spectrum of the sampled sequence,
:math:`S_\Delta(\boldsymbol f) = \sum_{\boldsymbol m} S(\boldsymbol f + \boldsymbol m/\Delta)`
on :math:`|f| \le 1/(2\Delta)`, i.e. :func:`roughgp.gp.fourier.acvf_to_psd` of the sampled ACVF.
"""

from __future__ import annotations

import numpy as np

from roughgp.common.checks import check_finite
from roughgp.common.grid import centred_frequencies, centred_lags, normalize

__all__ = ["periodogram", "welch", "empirical_acvf", "near_direction"]


def _data(z, name="z"):
    z = np.asarray(z, dtype=np.float64)
    if z.ndim not in (1, 2) or z.size < 2:
        raise ValueError(f"{name} must be a profile (n,) or a surface (ny, nx) with at least "
                         f"2 points, got shape {z.shape}")
    check_finite(name, z)
    return z


def periodogram(z, spacing=1.0, demean=True):
    r"""Two-sided periodogram :math:`I(\boldsymbol f) = \frac{\Delta^D}{N}\,
    |\sum_{\boldsymbol x} z(\boldsymbol x)\, e^{-i2\pi\boldsymbol f^\top\boldsymbol x}|^2`.

    Returns ``(freqs, power)``: ``freqs`` of shape ``(*z.shape, D)`` on the centred FFT grid, and
    ``power`` of shape ``z.shape``. Its expectation is the aliased PSD smoothed by the Fejér
    kernel; at each frequency it scatters like :math:`S\cdot\chi^2_2/2` (an exponential law).
    """
    z = _data(z)
    shape, spacing = normalize(z.shape, spacing)
    if demean:
        z = z - z.mean()
    power = np.abs(np.fft.fftshift(np.fft.fftn(z))) ** 2 * np.prod(spacing) / z.size
    return centred_frequencies(shape, spacing), power


def welch(z, spacing=1.0, segment_length=256, overlap=0.5, window="hann"):
    """Welch's averaged, windowed periodogram of a profile (two-sided, eq 5 scaling).

    Returns ``(freqs, power)`` with ``freqs`` of shape (m, 1) on the centred grid of one
    segment. Averaging segments trades resolution (1 / (segment_length * spacing)) for a
    variance reduced by roughly the number of segments.
    """
    z = _data(z)
    if z.ndim != 1:
        raise ValueError(f"welch takes a profile of shape (n,), got shape {z.shape}")
    if not (isinstance(segment_length, (int, np.integer)) and 2 <= segment_length <= z.size):
        raise ValueError(f"segment_length must be an integer in [2, {z.size}] (the profile "
                         f"length), got {segment_length!r}")
    if not 0 <= overlap < 1:
        raise ValueError(f"overlap must be in [0, 1), got {overlap!r}")
    (spacing,) = normalize(z.shape, spacing)[1]
    from scipy import signal  # imported here: 0.5-0.8 s that texture and the filters do not need

    freqs, power = signal.welch(z, fs=1.0 / spacing, window=window, nperseg=segment_length,
                                noverlap=int(overlap * segment_length), return_onesided=False,
                                scaling="density", detrend="constant")
    order = np.argsort(freqs, kind="stable")
    return freqs[order][:, None], power[order]


def empirical_acvf(z, spacing=1.0, max_lag=None, unbiased=False, demean=True):
    r"""Sample ACVF of a profile or surface, on centred lags up to ``max_lag`` per axis.

    ``unbiased=False`` gives :math:`\hat r(\boldsymbol k) = \frac1N\sum z(\boldsymbol x)
    z(\boldsymbol x + \boldsymbol k)` (the biased estimate: its expectation is
    :math:`\prod_d(1-|k_d|/n_d)\, r(\boldsymbol k)` for a known zero mean, it is positive
    semi-definite, and its transform is the periodogram); ``unbiased=True`` divides by the
    number of pairs at each lag instead.

    Args:
        max_lag: largest lag index per axis (int or one per axis), default ``n - 1``.

    Returns ``(lags, values)``: lags of shape ``(*m, D)`` with components in (x, y) order and the
    estimate of shape ``m`` where ``m = 2 * max_lag + 1`` per axis.
    """
    z = _data(z)
    shape, spacing = normalize(z.shape, spacing)
    try:
        max_lag = np.broadcast_to(np.asarray(shape) - 1 if max_lag is None else max_lag,
                                  (len(shape),)).astype(int)
    except ValueError:
        raise ValueError(f"max_lag must be an integer or one integer per axis of z "
                         f"(shape {shape}), got {max_lag!r}") from None
    if np.any(max_lag < 0) or np.any(max_lag >= np.asarray(shape)):
        raise ValueError(f"max_lag must be in [0, n - 1] per axis (n = {shape}), "
                         f"got {max_lag.tolist()}")
    if demean:
        z = z - z.mean()
    padded = tuple(2 * n for n in shape)
    axes = tuple(range(z.ndim))
    spectrum = np.fft.rfftn(z, padded, axes=axes)
    products = np.fft.irfftn(spectrum * np.conj(spectrum), padded, axes=axes)
    products = np.fft.fftshift(products)  # lag zero at index n of each axis (2n points)
    window = tuple(slice(n - m, n + m + 1) for n, m in zip(shape, max_lag))
    products = products[window]
    if unbiased:
        counts = 1.0
        for axis, (n, m) in enumerate(zip(shape, max_lag)):
            c = n - np.abs(np.arange(-m, m + 1))
            counts = np.multiply.outer(counts, c) if axis else c.astype(float)
        values = products / counts
    else:
        values = products / z.size
    lags = centred_lags(tuple(2 * m + 1 for m in max_lag), spacing)
    return lags, values



def near_direction(lags, angle, half_width):
    """Select the lags of a grid that lie within ``half_width`` of the line through lag zero
    in the direction ``angle`` (radians, counter-clockwise from x), e.g. to compare an
    empirical ACVF with eq 18 along and across the grooves at the grid's own lags (no
    interpolation across a sharp ridge).

    Args:
        lags: shape ``(..., 2)``, components (x, y) (as from :func:`empirical_acvf`).
        half_width: > 0, in the lags' unit.

    Returns:
        ``(mask, distance)``: the boolean mask of the selected lags (shape ``lags.shape[:-1]``)
        and their distance along the direction (>= 0 ahead of lag zero, < 0 behind it).
    """
    lags = np.asarray(lags, dtype=np.float64)
    if lags.ndim < 2 or lags.shape[-1] != 2:
        raise ValueError(f"lags must have shape (..., 2), got {lags.shape}")
    if not np.isfinite(half_width) or half_width <= 0:
        raise ValueError(f"half_width must be > 0, got {half_width!r}")
    along = lags[..., 0] * np.cos(angle) + lags[..., 1] * np.sin(angle)
    across = -lags[..., 0] * np.sin(angle) + lags[..., 1] * np.cos(angle)
    mask = np.abs(across) <= half_width
    return mask, along[mask]
