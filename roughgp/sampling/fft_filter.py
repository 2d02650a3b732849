r"""The classic FFT-filter generator of rough surfaces (e.g. Hu & Tonder 1992): a baseline.

White noise is filtered in the frequency domain by the square root of the PSD on the grid's
own FFT frequencies and transformed back. The result is a *periodic* field: its covariance is
circulant with eigenvalues :math:`S(\boldsymbol f_k)/\Delta^D` on the grid itself, so it equals eq 10
only where the ACVF has decayed within half the grid and the PSD within the Nyquist band.
Correlation lengths comparable to the grid (figure 2's lambda_a = 500 on 2000 points) wrap
around: the method is fast and approximate, which is why the book uses it as the speed baseline
for the exact samplers of :mod:`roughgp.sampling`.
"""

from __future__ import annotations

import numpy as np
import scipy.fft

from roughgp.common.grid import normalize

__all__ = ["fft_filter"]


def fft_filter(psd, shape, *, spacing=1.0, n_samples=1, seed=None):
    """Draw ``n_samples`` periodic surfaces with PSD ``psd`` (a function of frequencies of
    shape (..., D), eq 5 convention) on a grid; shape ``(n_samples, *shape)``."""
    from roughgp.common.checks import as_generator as _rng  # the one seed convention

    shape, spacing = normalize(shape, spacing)
    if not isinstance(n_samples, (int, np.integer)) or n_samples < 1:
        raise ValueError(f"n_samples must be an integer >= 1, got {n_samples!r}")
    rng = _rng(seed)
    axes = [np.fft.fftfreq(n, d) for n, d in zip(shape, spacing)]
    freqs = np.stack(np.meshgrid(*axes, indexing="ij")[::-1], axis=-1)
    eigenvalues = np.asarray(psd(freqs), dtype=np.float64) / np.prod(spacing)
    if np.any(eigenvalues < 0) or not np.all(np.isfinite(eigenvalues)):
        raise ValueError("psd must be finite and >= 0 on the grid's frequencies")
    gain = np.sqrt(eigenvalues)
    del freqs
    out = np.empty((int(n_samples), *shape))
    for k in range(int(n_samples)):
        spectrum = scipy.fft.fftn(rng.standard_normal(shape), workers=-1, overwrite_x=True)
        spectrum *= gain
        out[k] = scipy.fft.ifftn(spectrum, workers=-1, overwrite_x=True).real
    return out
