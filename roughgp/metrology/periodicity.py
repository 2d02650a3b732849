r"""How periodic a profile is, and how much of it is short-wavelength: the two measures by
which section 3.3 of the paper judges its simulated turned surfaces ("decreasing
periodicity", "additional short wavelengths").

Both work along x (the last axis): on a profile ``z[ix]``, or row by row on a surface
``z[iy, ix]`` (then averaged over the rows).
"""

from __future__ import annotations

import numpy as np

from roughgp.common.checks import check_finite, check_integer, check_positive

__all__ = ["periodicity", "short_wavelength_share"]


def _rows(z):
    z = np.asarray(z, dtype=np.float64)
    if z.ndim not in (1, 2) or z.shape[-1] < 4:
        raise ValueError(f"z must be a profile (n,) or a surface (ny, nx) with n, nx >= 4, "
                         f"got shape {z.shape}")
    check_finite("z", z)
    rows = np.atleast_2d(z)
    return rows - rows.mean(axis=1, keepdims=True)


def periodicity(z, period, spacing=1.0, n_periods=5):
    r"""The unbiased autocorrelation at lags :math:`k \cdot` ``period``, k = 1..``n_periods``:
    :math:`\hat r(kP) / \hat r(0)` with :math:`\hat r(\tau) = \frac{1}{n - \tau/\Delta}\sum_i
    z_i z_{i + \tau/\Delta}` (the profile's mean removed), averaged over the rows of a surface.
    A strictly periodic profile gives values near 1 at every k; a periodicity that decays
    gives values that fall with k.

    Args:
        z: profile (n,) or surface (ny, nx), finite.
        period: > 0, in units of ``spacing`` (rounded to the nearest whole number of samples).
        spacing: > 0. n_periods: >= 1 with ``n_periods * period`` shorter than the profile.

    Returns:
        array of shape (n_periods,).
    """
    rows = _rows(z)
    check_positive("period", period)
    check_positive("spacing", spacing)
    n = rows.shape[1]
    n_periods = check_integer("n_periods", n_periods, 1)
    lags = np.rint(np.arange(1, n_periods + 1) * period / spacing).astype(int)
    if lags[-1] >= n:
        raise ValueError(f"n_periods * period = {lags[-1] * spacing:g} must be shorter than the "
                         f"profile ({n * spacing:g}); allowed n_periods: 1..{(n - 1) // max(lags[0], 1)}")
    r0 = np.mean(rows * rows)
    if not r0 > 0:
        raise ValueError("z must not be constant along x")
    values = [np.mean(rows[:, :-h] * rows[:, h:]) for h in lags]
    return np.asarray(values) / r0


def short_wavelength_share(z, cutoff_wavelength, spacing=1.0):
    """Share of the variance along x at wavelengths shorter than ``cutoff_wavelength``
    (periodogram of each row, mean removed; averaged over the rows of a surface).

    Args:
        z: profile (n,) or surface (ny, nx), finite.
        cutoff_wavelength: > 2 * spacing (the shortest wavelength on the grid), in units of
            ``spacing``.
        spacing: > 0.

    Returns:
        a number in [0, 1].
    """
    rows = _rows(z)
    check_positive("spacing", spacing)
    check_positive("cutoff_wavelength", cutoff_wavelength)
    if not cutoff_wavelength > 2 * spacing:
        raise ValueError(f"cutoff_wavelength must be > 2 * spacing = {2 * spacing:g} (the "
                         f"Nyquist wavelength), got {cutoff_wavelength!r}")
    power = np.abs(np.fft.rfft(rows, axis=1)) ** 2
    freqs = np.fft.rfftfreq(rows.shape[1], spacing)
    total = power[:, 1:].sum()
    if not total > 0:
        raise ValueError("z must not be constant along x")
    return float(power[:, freqs > 1.0 / cutoff_wavelength].sum() / total)
