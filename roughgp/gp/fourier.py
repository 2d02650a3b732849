r"""The Wiener-Khinchin pair of eq 5 evaluated on a regular grid with the FFT.

A continuous Fourier integral is approximated by a Riemann sum over a centred grid:

.. math::
    S(\boldsymbol f_k) \approx \Delta^D \sum_j r(\boldsymbol\tau_j)
        e^{-i2\pi \boldsymbol f_k^\top \boldsymbol\tau_j}, \qquad
    r(\boldsymbol\tau_j) \approx \delta f^D \sum_k S(\boldsymbol f_k)
        e^{i2\pi \boldsymbol f_k^\top \boldsymbol\tau_j},

with lag spacing :math:`\Delta`, ``n`` points per axis and frequency spacing
:math:`\delta f = 1/(n\Delta)`. The two sums are exact inverses of each other; each differs from
the integral it stands for by two errors that the chapter "Notation" measures: *aliasing*
(the sum over lags sees :math:`\sum_m S(f + m/\Delta)`, Poisson's formula) and *truncation*
(the grid covers only :math:`|\tau| < n\Delta/2`, or :math:`|f| < 1/(2\Delta)`).

Grids are centred: index ``n // 2`` of each axis holds lag (or frequency) zero, the layout of
``numpy.fft.fftshift``; the layout conventions are those of :mod:`roughgp.common.grid`.
"""

from __future__ import annotations

import numpy as np

from roughgp.common.grid import centred_frequencies, centred_lags, normalize

__all__ = ["lag_grid", "frequency_grid", "acvf_to_psd", "psd_to_acvf", "duality_errors"]

lag_grid = centred_lags
"""Centred lags of shape ``(*shape, D)``: see :func:`roughgp.common.grid.centred_lags`."""

frequency_grid = centred_frequencies
"""Centred frequencies matching :func:`lag_grid`: see :func:`roughgp.common.grid.centred_frequencies`."""


def acvf_to_psd(values, spacing=1.0):
    """PSD on :func:`frequency_grid` from ACVF values on :func:`lag_grid` (eq 5, forward).

    The ACVF of a real process is even, so the transform is real up to rounding; the
    imaginary part is dropped after a check that it is negligible.
    """
    values = np.asarray(values, dtype=np.float64)
    shape, spacing = normalize(values.shape, spacing)
    spectrum = np.fft.fftshift(np.fft.fftn(np.fft.ifftshift(values))) * np.prod(spacing)
    _check_real(spectrum, "values (the ACVF must be even: r(tau) = r(-tau))")
    return spectrum.real


def psd_to_acvf(values, spacing=1.0):
    """ACVF on :func:`lag_grid` (lag spacing ``spacing``) from PSD values on
    :func:`frequency_grid` of the same shape and spacing (eq 5, inverse)."""
    values = np.asarray(values, dtype=np.float64)
    shape, spacing = normalize(values.shape, spacing)
    acvf = np.fft.fftshift(np.fft.ifftn(np.fft.ifftshift(values))) / np.prod(spacing)
    _check_real(acvf, "values (the PSD must be even: S(f) = S(-f))")
    return acvf.real


def _check_real(array, what):
    scale = np.abs(array).max()
    if scale > 0 and np.abs(array.imag).max() > 1e-8 * scale:
        raise ValueError(f"{what}: its transform has an imaginary part of "
                         f"{np.abs(array.imag).max() / scale:.1e} of its largest value. On an "
                         f"even-size grid the most negative lag/frequency of an axis has no "
                         f"mirror: a 2-D function that is even but not symmetric about each "
                         f"axis (e.g. a rotated one) needs odd sizes or to vanish at the edges")


def duality_errors(acvf, psd, shape, spacing=1.0, band=None):
    """Measure eq 5 on a grid for an ACVF with a closed-form PSD.

    Evaluates ``acvf`` on :func:`lag_grid` and ``psd`` on :func:`frequency_grid` (both
    functions of points of shape (..., D)), transforms each into the other, and returns:

    * ``"forward"``: ``max |FFT(ACVF) - PSD|`` over frequencies with ``|f| <= band`` (all if
      ``None``), relative to the PSD's largest value -- the aliasing error;
    * ``"inverse"``: ``max |IFFT(PSD) - ACVF|`` over all lags, relative to ACVF(0);
    * ``"lag0_deficit"``: (ACVF(0) - IFFT(PSD)(0)) / ACVF(0), the share of the variance in
      PSD mass beyond the grid's Nyquist frequency -- the truncation error.
    """
    lags, freqs = lag_grid(shape, spacing), frequency_grid(shape, spacing)
    r, s = np.asarray(acvf(lags)), np.asarray(psd(freqs))
    s_numeric, r_numeric = acvf_to_psd(r, spacing), psd_to_acvf(s, spacing)
    mask = np.ones(s.shape, bool) if band is None else np.linalg.norm(freqs, axis=-1) <= band
    centre = tuple(n // 2 for n in r.shape)
    return {
        "forward": float(np.abs(s_numeric - s)[mask].max() / np.abs(s).max()),
        "inverse": float(np.abs(r_numeric - r).max() / r[centre]),
        "lag0_deficit": float((r[centre] - r_numeric[centre]) / r[centre]),
    }
