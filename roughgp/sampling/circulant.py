r"""Exact sampling on a grid by circulant embedding (Wood & Chan 1994; Dietrich & Newsam 1997).

The covariance of a stationary field on a regular ``(ny, nx)`` grid is block-Toeplitz. Wrapping
the ACVF periodically on a larger torus of ``(my, mx)`` points, ``my >= 2 (ny - 1)`` and
``mx >= 2 (nx - 1)``, makes it block-circulant, diagonalised by the 2-D FFT: its eigenvalues are
``Lambda = FFT(c)`` of the wrapped ACVF ``c``. When every eigenvalue is >= 0 the torus field

.. math::  \mathbf w = \operatorname{FFT}\!\left(\sqrt{\Lambda / M}\,(\boldsymbol\varepsilon_1 + i\boldsymbol\varepsilon_2)\right)

has the wrapped covariance, and its real and imaginary parts, cut to the grid, are two
independent *exact* draws of eq 10. Cost: O(M log M) for M torus points.

Slowly decaying or anisotropic ACVFs (eq 18 with figure 2's lambda_a = 500) give negative
eigenvalues on the minimal torus; the torus is then grown, per axis, until none is left beyond
a tolerance. Clipping negative eigenvalues makes the draw approximate: only done when asked
(``approximate=True``), and the clipped share of the variance is reported.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import scipy.fft

from roughgp.common.grid import normalize

__all__ = ["Embedding", "embed", "draw", "minimal_torus", "predict_torus", "wrapped_lags",
           "NotEmbeddableError"]

_BLOCK_POINTS = 2**20  # ACVF evaluated on about this many torus points at a time (peak memory)


class NotEmbeddableError(ValueError):
    """The ACVF's circulant embedding keeps negative eigenvalues within the allowed torus."""


@dataclass(frozen=True)
class Embedding:
    """A non-negative (or explicitly clipped) circulant embedding of a grid covariance.

    Attributes:
        grid_shape, spacing: the grid it samples (array order).
        torus_shape: the torus ``(my, mx)`` (or ``(m,)``).
        scale: ``sqrt(max(Lambda, 0) / M)`` on the torus, the FFT multiplier of a draw.
        min_eigenvalue: the most negative eigenvalue relative to the mean eigenvalue r(0).
        clipped_fraction: sum of the clipped negative eigenvalues / trace (0 when exact).
        tries: torus shapes tried, with their relative most negative eigenvalue.
    """

    grid_shape: tuple
    spacing: tuple
    torus_shape: tuple
    scale: np.ndarray
    min_eigenvalue: float
    clipped_fraction: float
    tries: tuple

    @property
    def exact(self) -> bool:
        return self.clipped_fraction == 0.0

    @property
    def nbytes(self) -> int:
        return int(self.scale.nbytes)


def wrapped_lags(torus_shape, spacing, rows=slice(None)):
    """Lags of the torus points in (x, y) order, wrapped to [-m/2, m/2) per axis."""
    axes = [np.where(j <= m // 2, j, j - m) * d
            for j, m, d in ((np.arange(m), m, d) for m, d in zip(torus_shape, spacing))]
    axes[0] = axes[0][rows]
    mesh = np.meshgrid(*axes, indexing="ij")
    return np.stack(mesh[::-1], axis=-1)


def _wrapped_acvf(acvf, torus_shape, spacing):
    values = np.empty(torus_shape, dtype=np.float64)
    block_rows = max(1, _BLOCK_POINTS // int(np.prod(torus_shape[1:], dtype=np.int64)))
    for start in range(0, torus_shape[0], block_rows):
        rows = slice(start, min(start + block_rows, torus_shape[0]))
        values[rows] = acvf(wrapped_lags(torus_shape, spacing, rows))
    if not np.all(np.isfinite(values)):
        raise ValueError("kernel returned non-finite covariances on the embedding torus")
    return values


def _outer_level(base):
    """max |c| over the torus points whose wrapped lag exceeds a quarter of the torus along
    some axis (the outer half of each axis), relative to c(0)."""
    level = 0.0
    for axis, m in enumerate(base.shape):
        outer = [slice(None)] * base.ndim
        outer[axis] = slice(m // 4 + 1, m - m // 4)
        if m // 4 + 1 < m - m // 4:
            level = max(level, float(np.abs(base[tuple(outer)]).max()))
    return level / float(base.flat[0])


def _eigenvalues(acvf, torus_shape, spacing):
    """Eigenvalues of the circulant matrix, r(0), the ACVF level on the torus' outer half, and
    the rounding level of the eigenvalues relative to r(0): an FFT of M values computes each
    output to about ``eps * log2(M) * sum|c|``, so a negative eigenvalue of that size is
    rounding, not indefiniteness (it matters on large tori of slowly decaying ACVFs)."""
    base = _wrapped_acvf(acvf, torus_shape, spacing)
    variance = float(base.flat[0])
    if variance <= 0:
        raise ValueError(f"the ACVF at lag 0 must be > 0, got {variance}")
    outer = _outer_level(base)
    rounding = (np.finfo(np.float64).eps * max(math.log2(base.size), 1.0)
                * float(np.abs(base).sum()) / variance)
    eig = scipy.fft.fftn(base, workers=-1, overwrite_x=True).real
    return eig, variance, outer, rounding


def _boundary_level(acvf, torus_shape, spacing, axis):
    """max |r| on the torus' wrap boundary of ``axis``, relative to r(0)."""
    lags = wrapped_lags(torus_shape, spacing) if len(torus_shape) == 1 else None
    if lags is None:
        other = 1 - axis
        m_other, d_other = torus_shape[other], spacing[other]
        line = np.where(np.arange(m_other) <= m_other // 2, np.arange(m_other),
                        np.arange(m_other) - m_other) * d_other
        edge = np.full_like(line, (torus_shape[axis] // 2) * spacing[axis])
        # components in (x, y) order: array axis 0 is y, axis 1 is x
        points = np.stack([line, edge] if axis == 0 else [edge, line], axis=-1)
    else:
        points = np.array([[(torus_shape[0] // 2) * spacing[0]]])
    zero = np.zeros((1, len(torus_shape)))
    return float(np.max(np.abs(acvf(points))) / acvf(zero)[0])


def _grow(m):
    return scipy.fft.next_fast_len(int(np.ceil(m * 1.25)), real=False)


def minimal_torus(shape):
    """The smallest torus of an embedding: ``2 (n - 1)`` per axis, up to a fast FFT size."""
    return tuple(scipy.fft.next_fast_len(max(2 * (n - 1), 1), real=False) for n in shape)


def predict_torus(acvf, shape, spacing, *, boundary_level=1e-5, max_points=2**27):
    """A cheap guess of the torus an exact embedding needs: grow the minimal torus, the axis
    with the larger value first, until the ACVF on every wrap boundary is below
    ``boundary_level`` x r(0) (or the torus would exceed ``max_points``). No FFT is taken."""
    shape, spacing = normalize(shape, spacing)
    spacing = tuple(float(d) for d in spacing)
    torus = list(minimal_torus(shape))
    while True:
        levels = [_boundary_level(acvf, tuple(torus), spacing, a) for a in range(len(shape))]
        axis = int(np.argmax(levels))
        grown = _grow(torus[axis])
        if levels[axis] <= boundary_level or np.prod(torus) // torus[axis] * grown > max_points:
            return tuple(torus)
        torus[axis] = grown


def embed(acvf, shape, spacing=1.0, *, tolerance=1e-10, approximate=False,
          max_clipped_fraction=1e-4, max_points=2**27, boundary_level=1e-5):
    """Find a circulant embedding of the grid covariance of ``acvf``.

    Starts from :func:`predict_torus` (the minimal torus grown until the ACVF on each wrap
    boundary is below ``boundary_level`` x r(0)), then checks the eigenvalues and grows the
    axis with the larger boundary value by 25 % until the most negative eigenvalue is
    >= -``tolerance`` x r(0). On a large torus the FFT's own rounding (about
    ``eps * log2(M) * sum|c| / r(0)``, which grows with M) replaces ``tolerance`` when it is
    larger.

    With ``approximate=True`` the torus is instead grown only until the negative eigenvalues
    hold less than ``max_clipped_fraction`` of the trace; they are then set to zero and
    that share is reported as ``clipped_fraction``.

    Raises:
        NotEmbeddableError: when the torus would exceed ``max_points`` before the criterion
            holds, or at once when the ACVF is already below ``tolerance`` x r(0) on the outer
            half of the torus while significant negative eigenvalues remain: a larger torus then
            only samples the same (non-positive-definite) spectrum more finely, so the ACVF
            sampled at this spacing is not a valid covariance. The message says how negative
            the eigenvalues were and what was tried.
    """
    shape, spacing = normalize(shape, spacing)
    spacing = tuple(float(d) for d in spacing)
    torus = predict_torus(acvf, shape, spacing, max_points=max_points,
                          boundary_level=1e3 * boundary_level if approximate else boundary_level)
    torus = list(torus)
    tries = []
    while True:
        torus_shape = tuple(torus)
        eig, variance, outer_level, rounding = _eigenvalues(acvf, torus_shape, spacing)
        min_rel = float(eig.min() / variance)
        tolerance_here = max(tolerance, rounding)
        significant = eig < -tolerance_here * variance  # smaller ones are rounding, both modes
        negative_share = float(-eig[significant].sum() / eig.sum())
        tries.append((torus_shape, min_rel))
        done = ((negative_share < max_clipped_fraction) if approximate
                else (min_rel >= -tolerance_here))
        if done:
            clipped = negative_share if approximate else 0.0
            scale = np.sqrt(np.clip(eig, 0.0, None) / eig.size)
            return Embedding(shape, spacing, torus_shape, scale, min_rel, clipped, tuple(tries))
        if outer_level <= tolerance:
            raise NotEmbeddableError(
                f"the ACVF is not positive definite on a grid of spacing {spacing}: on the "
                f"torus {torus_shape} its circulant embedding has eigenvalues down to "
                f"{min_rel:.3g} x r(0) ({negative_share:.2g} of the trace) although the ACVF is "
                f"already below {tolerance:g} x r(0) on the torus' outer half, so no larger "
                f"torus removes them. A valid kernel (eq 5: its PSD is >= 0) is needed.")
        levels = [_boundary_level(acvf, torus_shape, spacing, a) for a in range(len(shape))]
        axis = int(np.argmax(levels))
        torus[axis] = _grow(torus[axis])
        if np.prod(torus) > max_points:
            raise NotEmbeddableError(
                f"circulant embedding of shape {shape} (spacing {spacing}) keeps negative "
                f"eigenvalues: most negative {min_rel:.3g} x r(0) (tolerance {tolerance:g}), "
                f"{negative_share:.2g} of the trace, on the largest torus tried, "
                f"{torus_shape}; tried {[t for t, _ in tries]}; the next ({tuple(torus)}) "
                f"exceeds max_points = {max_points}. Use approximate=True to clip (the lost "
                f"variance is reported), a smaller grid, or method='cholesky'.")


def draw(embedding: Embedding, n_samples: int, rng: np.random.Generator, dtype=np.float64,
         device=None):
    """``n_samples`` draws from an embedding, two per complex FFT; shape (n, *grid_shape).

    ``dtype=np.float32`` runs the FFTs in single precision (complex64), halving memory.
    ``device`` (a ``torch.device``, see :mod:`roughgp.common.device`) runs the FFTs there with noise
    from a torch generator on the device seeded from ``rng``; a numpy array is returned.
    """
    if device is not None:
        return _draw_on_device(embedding, n_samples, rng, dtype, device)
    complex_dtype = np.complex64 if np.dtype(dtype) == np.float32 else np.complex128
    real_dtype = np.float32 if complex_dtype == np.complex64 else np.float64
    scale = embedding.scale.astype(real_dtype, copy=False)
    grid = tuple(slice(0, n) for n in embedding.grid_shape)
    out = np.empty((n_samples, *embedding.grid_shape), dtype=real_dtype)
    noise = np.empty(embedding.torus_shape, dtype=complex_dtype)
    for k in range(0, n_samples, 2):
        rng.standard_normal(out=noise.view(real_dtype), dtype=real_dtype)
        noise *= scale
        field = scipy.fft.fftn(noise, workers=-1, overwrite_x=True)
        out[k] = field.real[grid]
        if k + 1 < n_samples:
            out[k + 1] = field.imag[grid]
    return out


_ON_DEVICE: list = []  # (embedding, device, dtype, scale tensor): the last few moved there
_ON_DEVICE_SIZE = 4


def _device_scale(embedding, device, real_dtype):
    """``embedding.scale`` on ``device`` (kept for the next draws of the same embedding)."""
    import torch

    for entry in _ON_DEVICE:
        if entry[0] is embedding and entry[1] == device and entry[2] == real_dtype:
            return entry[3]
    scale = torch.as_tensor(embedding.scale, device=device).to(real_dtype)
    _ON_DEVICE.append((embedding, device, real_dtype, scale))
    del _ON_DEVICE[:-_ON_DEVICE_SIZE]
    return scale


def _draw_on_device(embedding, n_samples, rng, dtype, device):
    import torch

    from roughgp.common.device import check_memory, generator

    real_dtype = torch.float32 if np.dtype(dtype) == np.float32 else torch.float64
    m = int(np.prod(embedding.torus_shape))
    item = 4 if real_dtype == torch.float32 else 8
    # the scale, the complex noise and its FFT, and the draws on the grid
    check_memory(item * (m + 4 * m + n_samples * int(np.prod(embedding.grid_shape))),
                 device, f"circulant draws on the torus {embedding.torus_shape}")
    scale = _device_scale(embedding, device, real_dtype)
    gen = generator(rng, device)
    grid = tuple(slice(0, n) for n in embedding.grid_shape)
    out = torch.empty((n_samples, *embedding.grid_shape), dtype=real_dtype, device=device)
    dims = tuple(range(len(embedding.torus_shape)))
    for k in range(0, n_samples, 2):
        noise = torch.randn((*embedding.torus_shape, 2), generator=gen, dtype=real_dtype,
                            device=device)
        noise = torch.view_as_complex(noise) * scale
        field = torch.fft.fftn(noise, dim=dims)
        out[k] = field.real[grid]
        if k + 1 < n_samples:
            out[k + 1] = field.imag[grid]
    return out.cpu().numpy()
