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

Smooth truncation (``truncation="smooth"``, the default; Bachmayr, Graham, Nguyen & Scheichl
2020, cf. the cut-off embedding of Gneiting, Sevcikova, Percival, Schlather & Jiang 2006): the
ACVF is multiplied, per axis, by a C-infinity taper that is 1 on every lag two grid points
have (``|tau_a| <= (n_a - 1) d_a``) and falls to 0 at the torus' wrap. The covariance between
grid points is unchanged, so the draws stay exact on the grid whenever the eigenvalues are
>= 0; only the margin beyond the grid's lags is searched, and the torus shrinks toward
``(2 n)^D`` (figure 2 on 2000 x 2000: 4032 x 4536 instead of 6250 x 12250). The search
runs on a coarser copy of the grid (spacing s d, torus <= 2^20 points) and is then checked once
on the full torus (float64: a float32 FFT's rounding, ~6e-8 log2(M) sum|c| / r(0), is above
figure 2's smallest eigenvalue, so it could not prove the embedding non-negative).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import scipy.fft

from roughgp.common.grid import normalize
from roughgp.sampling import truncation as tapering
from roughgp.sampling.truncation import NotEmbeddableError, wrapped_lags

__all__ = ["Embedding", "embed", "draw", "minimal_torus", "predict_torus", "wrapped_lags",
           "NotEmbeddableError", "TRUNCATIONS", "compare_truncations"]

TRUNCATIONS = ("smooth", "none")
_COARSE_POINTS = 2**20  # the coarse search's torus holds at most about this many points


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
        truncation: ``"smooth"`` (ACVF tapered beyond the grid's lags) or ``"none"``.
    """

    grid_shape: tuple
    spacing: tuple
    torus_shape: tuple
    scale: np.ndarray
    min_eigenvalue: float
    clipped_fraction: float
    tries: tuple
    truncation: str = "none"

    @property
    def exact(self) -> bool:
        return self.clipped_fraction == 0.0

    @property
    def nbytes(self) -> int:
        return int(self.scale.nbytes)


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
    base = tapering.wrapped_acvf(acvf, torus_shape, spacing)
    variance = float(base.flat[0])
    if variance <= 0:
        raise ValueError(f"the ACVF at lag 0 must be > 0, got {variance}")
    outer = _outer_level(base)
    rounding = tapering.rounding_level(base, variance)
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


def _predict_wrapped(acvf, shape, spacing, *, boundary_level=1e-5, max_points=2**27):
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


def _embed_wrapped(acvf, shape, spacing=1.0, *, tolerance=1e-10, approximate=False,
                   max_clipped_fraction=1e-4, max_points=2**27, boundary_level=1e-5):
    """The plain wrap (``truncation="none"``) of :func:`embed`.

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
    torus = _predict_wrapped(acvf, shape, spacing, max_points=max_points,
                             boundary_level=1e3 * boundary_level if approximate else boundary_level)
    torus = list(torus)
    tries = []
    while True:
        torus_shape = tuple(torus)
        eig, variance, outer_level, rounding = _eigenvalues(acvf, torus_shape, spacing)
        done, min_rel, negative_share = tapering.criterion(
            eig, variance, rounding, tolerance, approximate, max_clipped_fraction)
        tries.append((torus_shape, min_rel))
        if done:
            clipped = negative_share if approximate else 0.0
            scale = np.sqrt(np.clip(eig, 0.0, None) / eig.size)
            return Embedding(shape, spacing, torus_shape, scale, min_rel, clipped, tuple(tries))
        if outer_level <= tolerance:
            raise tapering.not_valid_error(spacing, f"on the torus {torus_shape}", min_rel,
                                           negative_share, tolerance, "on the torus' outer half")
        levels = [_boundary_level(acvf, torus_shape, spacing, a) for a in range(len(shape))]
        axis = int(np.argmax(levels))
        torus[axis] = _grow(torus[axis])
        if np.prod(torus) > max_points:
            raise tapering.too_large_error(shape, spacing, min_rel, negative_share, tolerance,
                                           torus_shape, [t for t, _ in tries], torus,
                                           max_points)


def predict_torus(acvf, shape, spacing, *, boundary_level=1e-5, max_points=2**27,
                  truncation="smooth", tolerance=1e-10, approximate=False,
                  max_clipped_fraction=1e-4):
    """The torus an embedding of ``acvf`` on the grid is expected to need.

    ``truncation="smooth"``: the margin beyond the grid's lags found on a coarse copy of the
    grid (spacing ``s d``, ``s`` chosen so its torus holds <= 2^20 points): a few FFTs of that
    size (doubling, then two bisections), cached nowhere (``embed`` is). ``"none"``: the
    minimal torus grown until the ACVF on every wrap boundary is below ``boundary_level`` x
    r(0), no FFT.
    """
    shape, spacing = normalize(shape, spacing)
    spacing = tuple(float(d) for d in spacing)
    if truncation == "none":
        return _predict_wrapped(acvf, shape, spacing, boundary_level=boundary_level,
                                max_points=max_points)
    _check_truncation(truncation)
    options = dict(tolerance=tolerance, approximate=approximate,
                   max_clipped_fraction=max_clipped_fraction, max_points=max_points)
    return _predict_smooth(acvf, shape, spacing, **options)[0]


def _predict_smooth(acvf, shape, spacing, **options):
    """(torus, the search's result when the coarse copy is the grid itself, else None)."""
    minimal = int(np.prod(minimal_torus(shape), dtype=np.int64))
    ratio = minimal / _COARSE_POINTS
    factor = max(1, math.ceil(math.sqrt(ratio) if len(shape) == 2 else ratio))
    coarse = tuple(math.ceil((n - 1) / factor) + 1 for n in shape)
    coarse_spacing = tuple(d * factor for d in spacing)
    def fine(coarse_margins):
        # the same outer extent of taper on the fine grid (the coarse grid's lags reach a bit
        # further)
        return tuple(k * factor + (c - 1) * factor - (n - 1)
                     for k, c, n in zip(coarse_margins, coarse, shape))

    implied = None if factor == 1 else (shape, spacing,
                                        lambda m: tapering.torus_of(shape, fine(m)))
    found = tapering.search_margins(acvf, coarse, coarse_spacing, implied=implied, **options)
    return tapering.torus_of(shape, fine(found[0])), (found if factor == 1 else None)


def _check_truncation(truncation):
    if truncation not in TRUNCATIONS:
        raise ValueError(f"truncation must be one of {TRUNCATIONS}, got {truncation!r}")


def embed(acvf, shape, spacing=1.0, *, tolerance=1e-10, approximate=False,
          max_clipped_fraction=1e-4, max_points=2**27, boundary_level=1e-5,
          truncation="smooth"):
    """Find a circulant embedding of the grid covariance of ``acvf`` (eq 10's R).

    ``truncation="smooth"`` (default): the ACVF is tapered beyond the grid's lags (module
    docstring), so R itself is untouched; the margin of taper is found by
    :func:`predict_torus` on a coarse copy of the grid and checked once on the full torus
    (grown by 25 % per failure). ``truncation="none"``: the plain wrap of Wood & Chan, the
    minimal torus grown until the ACVF on each wrap boundary is below ``boundary_level`` x
    r(0), then by 25 % until the eigenvalues pass.

    Exact: the most negative eigenvalue is >= -``tolerance`` x r(0), or the FFT's own
    rounding (about ``eps * log2(M) * sum|c| / r(0)``, growing with M) when that is larger.
    With ``approximate=True`` the torus is instead grown only until the negative eigenvalues
    hold less than ``max_clipped_fraction`` of the trace; they are then set to zero and
    that share is reported as ``clipped_fraction``.

    Raises:
        NotEmbeddableError: when the torus would exceed ``max_points`` before the criterion
            holds, or at once when the ACVF is already below ``tolerance`` x r(0) beyond the
            grid's lags (smooth) or on the torus' outer half (none) while significant
            negative eigenvalues remain: the ACVF sampled at this spacing is then not a valid
            covariance. The message says how negative the eigenvalues were and what was tried.
    """
    _check_truncation(truncation)
    options = dict(tolerance=tolerance, approximate=approximate,
                   max_clipped_fraction=max_clipped_fraction, max_points=max_points)
    if truncation == "none":
        return _embed_wrapped(acvf, shape, spacing, boundary_level=boundary_level, **options)
    shape, spacing = normalize(shape, spacing)
    spacing = tuple(float(d) for d in spacing)
    torus, found = _predict_smooth(acvf, shape, spacing, **options)
    if found is None:  # searched on a coarse copy: check (and grow) on the full torus
        start = [(m - 2 * n + 1) // 2 for m, n in zip(torus, shape)]
        found = tapering.search_margins(acvf, shape, spacing, start=start, verify_only=True,
                                        **options)
    margins, eig, variance, min_rel, share, tries = found
    torus_shape = tapering.torus_of(shape, margins)
    clipped = share if approximate else 0.0
    eig = np.clip(eig, 0.0, None, out=eig)
    eig /= eig.size
    scale = np.sqrt(eig, out=eig)
    return Embedding(shape, spacing, torus_shape, scale, min_rel, clipped, tries, "smooth")


def draw(embedding: Embedding, n_samples: int, rng: np.random.Generator, dtype=np.float64,
         device=None):
    """``n_samples`` draws from an embedding, two per complex FFT; shape ``(n, *grid_shape)``.

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


def compare_truncations(acvf, shape, spacing, torus_shape):
    """For a smooth embedding on ``torus_shape``: the torus that the plain wrap is predicted to
    need (at least; its eigenvalue check may grow it further), both sizes over the grid's, and
    ``max |c - r| / r(0)`` over the grid's lags (0: R of eq 10 is unchanged)."""
    shape, spacing = normalize(shape, spacing)
    spacing = tuple(float(d) for d in spacing)
    plain = predict_torus(acvf, shape, spacing, truncation="none")
    grid = int(np.prod(shape))
    return dict(smooth=tuple(torus_shape), plain=plain,
                smooth_ratio=int(np.prod(torus_shape)) / grid, plain_ratio=int(np.prod(plain)) / grid,
                grid_lag_change=tapering.grid_lag_change(acvf, shape, spacing, torus_shape))
