r"""Smooth truncation of an ACVF beyond the lags of a grid, for circulant embedding (eq 10).

Every pair of points of an ``(n_y, n_x)`` grid has a lag with ``|tau_a| <= (n_a - 1) d_a``. On a
torus of ``m_a >= 2 n_a - 1`` points per axis these lags fall on distinct torus points, so the
ACVF may be changed freely beyond them without changing the grid covariance R of eq 10. Here it
is multiplied per axis by a C-infinity taper, 1 on the grid's lags and 0 at the torus' wrap
(Bachmayr, Graham, Nguyen & Scheichl 2020, "Unified analysis of periodization-based sampling
methods for Matern covariances"; cf. the cut-off embedding of Gneiting, Sevcikova, Percival,
Schlather & Jiang 2006). The wrapped ACVF then has no jump at the wrap, and a margin of taper of
a few correlation lengths beyond the grid's lags usually makes every eigenvalue >= 0; the
eigenvalues are always checked. :func:`search_margins` finds that margin per axis.
"""

from __future__ import annotations

import math

import numpy as np
import scipy.fft

__all__ = ["NotEmbeddableError", "taper", "torus_of", "tapered_acvf", "tapered_eigenvalues",
           "face_levels", "search_margins", "criterion", "wrapped_lags", "wrapped_acvf",
           "rounding_level", "grid_lag_change", "not_valid_error",
           "too_large_error"]

_BLOCK_POINTS = 2**20  # ACVF evaluated on about this many torus points at a time (peak memory)


class NotEmbeddableError(ValueError):
    """The ACVF's circulant embedding keeps negative eigenvalues within the allowed torus."""


def criterion(eig, variance, rounding, tolerance, approximate, max_clipped_fraction):
    """(done, min_rel, negative share) of eigenvalues: exact when the most negative one is
    within the tolerance (or the FFT's rounding), approximate when the significant negative
    ones hold less than ``max_clipped_fraction`` of the trace."""
    min_rel = float(eig.min() / variance)
    tolerance_here = max(tolerance, rounding)
    significant = eig < -tolerance_here * variance
    share = float(-eig[significant].sum() / eig.sum())
    done = share < max_clipped_fraction if approximate else min_rel >= -tolerance_here
    return done, min_rel, share


def taper(lags, inner, outer):
    """The C-infinity step of the smooth truncation: 1 for ``|lag| <= inner``, 0 for
    ``|lag| >= outer``, ``f(1 - u) / (f(1 - u) + f(u))`` with ``f(u) = exp(-1 / u)`` between."""
    lags = np.abs(np.asarray(lags, dtype=np.float64))
    if outer <= inner:
        return (lags <= inner).astype(np.float64)
    u = np.clip((lags - inner) / (outer - inner), 0.0, 1.0)
    with np.errstate(divide="ignore", over="ignore"):
        a = np.where(u < 1, np.exp(-1.0 / np.where(u < 1, 1.0 - u, 1.0)), 0.0)
        b = np.where(u > 0, np.exp(-1.0 / np.where(u > 0, u, 1.0)), 0.0)
    return a / (a + b)


def torus_of(shape, margins):
    """The torus ``next_fast_len(2 n - 1 + 2 k)`` per axis: grid lags ``-(n-1) .. n-1`` each on
    their own torus point, plus ``k`` points of taper beyond them on each side."""
    return tuple(scipy.fft.next_fast_len(2 * n - 1 + 2 * int(k), real=False)
                 for n, k in zip(shape, margins))


def tapered_acvf(acvf, torus_shape, spacing, shape):
    """The ACVF on the torus times the per-axis tapers (1 on the grid's lags, 0 at the wrap).
    Evaluated on half the torus: an ACVF is even, ``c(-tau) = c(tau)``."""
    values = np.empty(torus_shape, dtype=np.float64)
    half = torus_shape[0] // 2 + 1
    _fill_rows(values, acvf, spacing, half)
    m0 = torus_shape[0]
    source = values[1:(m0 - 1) // 2 + 1][::-1]
    for axis in range(1, len(torus_shape)):
        source = np.take(source, (-np.arange(torus_shape[axis])) % torus_shape[axis], axis=axis)
    values[half:] = source[:m0 - half]
    for axis, (m, n, d) in enumerate(zip(torus_shape, shape, spacing)):
        j = np.arange(m)
        w = taper(np.minimum(j, m - j) * d, (n - 1) * d, (m / 2) * d)
        if np.all(w == 1.0):
            continue
        values *= w.reshape([-1 if a == axis else 1 for a in range(len(torus_shape))])
    return values


def tapered_eigenvalues(acvf, torus_shape, spacing, shape):
    """Eigenvalues (the full torus, real) of the tapered embedding, r(0) and the rounding level
    of :func:`_eigenvalues`. One real FFT (rfftn) of the torus; the other half of the spectrum
    is its mirror image (the embedding is real and even)."""
    base = tapered_acvf(acvf, torus_shape, spacing, shape)
    variance = float(base.flat[0])
    if variance <= 0:
        raise ValueError(f"the ACVF at lag 0 must be > 0, got {variance}")
    rounding = rounding_level(base, variance)
    half = scipy.fft.rfftn(base, workers=-1).real
    del base
    last = torus_shape[-1]
    eig = np.empty(torus_shape, dtype=np.float64)
    eig[..., :half.shape[-1]] = half
    mirror = half
    for axis in range(len(torus_shape) - 1):
        mirror = np.take(mirror, (-np.arange(torus_shape[axis])) % torus_shape[axis], axis=axis)
    eig[..., half.shape[-1]:] = mirror[..., 1:last - half.shape[-1] + 1][..., ::-1]
    return eig, variance, rounding


def face_levels(acvf, shape, spacing, torus_shape, *, outer=False):
    """Per axis, ``max |r| / r(0)`` on lags beyond the grid's along it, ``(n_a - 1) d_a <= |tau_a|
    <= max(m_a / 2, n_a + 15) d_a`` (at most 64 of them), the other axes over all their lags on
    the torus (a ridge may cross the face beyond the grid's lags; a band, not the face alone,
    since an oscillating ACVF may vanish on the face itself). ``outer=True``: on the outer
    quarter of the torus beyond the grid's lags instead, ``max(m_a / 4, n_a - 1) <= |tau_a| /
    d_a <= m_a / 2``: what is left of the ACVF where the taper ends (an axis left at its
    minimal torus, ``m_a = 2 n_a``, has no taper: only its lags beyond the grid's count, the
    others are R's own and no torus changes them)."""
    zero = np.zeros((1, len(shape)))
    levels = []
    for axis in range(len(shape)):
        grids = [np.where(np.arange(m) <= m // 2, np.arange(m), np.arange(m) - m) * d
                 for m, d in zip(torus_shape, spacing)]
        n, m = shape[axis], torus_shape[axis]
        band = np.unique((np.linspace(max(m // 4, n - 1), m // 2, 64) if outer else
                          np.linspace(n - 1, max(m // 2, n + 15), 64)).round())
        grids[axis] = np.concatenate([-band, band]) * spacing[axis]
        mesh = np.meshgrid(*grids, indexing="ij")
        points = np.stack(mesh[::-1], axis=-1).reshape(-1, len(shape))
        levels.append(float(np.max(np.abs(acvf(points))) / acvf(zero)[0]))
    return levels


def search_margins(acvf, shape, spacing, *, tolerance, approximate, max_clipped_fraction,
                    max_points, start=None, verify_only=False, implied=None):
    """Margins (points of taper per axis) whose tapered embedding passes :func:`criterion`.

    From ``start`` (0 by default) the axes whose face level per point of taper is within 10x of
    the worst are doubled (by 1.25 with ``verify_only``, the check on the full torus) until the
    eigenvalues pass, then two bisections between the last failing and the passing margins
    (none with ``verify_only``). Returns ``(margins, eig, variance, min_rel, share, tries)``.

    The search stops early with :class:`NotEmbeddableError` when growing cannot help: when the
    ACVF is below ``tolerance`` beyond the grid's lags (:func:`face_levels`), or when it is
    below ``tolerance`` on the torus' outer quarter and the last :data:`STAGNANT_TRIES`
    doublings changed neither the most negative eigenvalue nor the negative share by more
    than :data:`STAGNANT_CHANGE` (the eigenvalues have converged to the ACVF's own spectrum,
    which is negative somewhere: it is not a valid covariance at this spacing).

    ``implied``: for a search on a coarse copy of a grid, ``(grid shape, grid spacing,
    function of the margins -> the grid's torus)``: margins whose grid torus exceeds
    ``max_points`` end the search before their coarse torus is evaluated (passing or not, no
    larger margins can help the grid), the error naming that grid (no torus of it tried),
    instead of doubling on the small coarse tori up to ``max_points`` (a 4096² grid: 26 s to
    refuse, now 1 s).
    """
    step = [max(1, math.ceil(n / 16)) for n in shape]
    tries = []

    def check(margins):
        torus = torus_of(shape, margins)
        if np.prod(torus, dtype=np.float64) > max_points:
            last = tries[-1] if tries else (torus, float("nan"), float("nan"))
            raise too_large_error(shape, spacing, last[1], last[2], tolerance, last[0],
                                  [t for t, _, _ in tries], torus, max_points)
        if implied is not None:
            # the grid's torus these margins imply is too large: whether they pass here or
            # not (then any passing ones are larger still), the grid's cannot be embedded, so
            # the coarse torus is not even evaluated
            grid_shape, grid_spacing, grid_torus = implied
            big = grid_torus(margins)
            if np.prod(big, dtype=np.float64) > max_points:
                raise too_large_error(grid_shape, grid_spacing, float("nan"), float("nan"),
                                      tolerance, None, [], big, max_points)
        eig, variance, rounding = tapered_eigenvalues(acvf, torus, spacing, shape)
        done, min_rel, share = criterion(eig, variance, rounding, tolerance, approximate,
                                          max_clipped_fraction)
        tries.append((torus, min_rel, share))
        return done, (list(margins), eig, variance, min_rel, share), torus

    margins, low = list(start) if start is not None else [0] * len(shape), None
    while True:
        done, found, torus = check(margins)
        if done:
            break
        levels = face_levels(acvf, shape, spacing, torus)
        if max(levels) <= tolerance:
            raise not_valid_error(spacing, f"on the torus {tries[-1][0]}", found[3], found[4],
                                  tolerance, "beyond the grid's lags")
        if not verify_only and _stagnant(tries) and \
                max(face_levels(acvf, shape, spacing, torus, outer=True)) <= tolerance:
            raise not_valid_error(spacing, f"from the torus {tries[-STAGNANT_TRIES - 1][0]} to "
                                  f"{tries[-1][0]}", found[3], found[4], tolerance,
                                  "where the taper ends")
        low = list(margins)
        badness = [lv / max(k, 1) for lv, k in zip(levels, margins)]  # per grid point: scale-free
        for a, b in enumerate(badness):
            if b >= 0.1 * max(badness):
                grown = math.ceil(1.25 * margins[a]) if verify_only else 2 * margins[a]
                margins[a] = max(grown, step[a])
    high = list(margins)
    for _ in range(0 if verify_only or low is None else 2):
        middle = [(h + lo) // 2 for h, lo in zip(high, low)]
        if torus_of(shape, middle) == torus_of(shape, high):
            break
        done, result, _ = check(middle)
        if done:
            high, found = middle, result
        else:
            low = middle
    return (*found, tuple((t, m) for t, m, _ in tries))


def too_large_error(shape, spacing, min_rel, share, tolerance, largest, tried, next_torus,
                    max_points):
    """The error for an embedding that still has negative eigenvalues (down to ``min_rel`` x
    r(0), ``share`` of the trace) on the ``largest`` of the tori ``tried`` when the next one
    would exceed ``max_points``; no torus ``tried``: the first, long enough for the ACVF's
    reach, already exceeds it."""
    if not tried:
        return NotEmbeddableError(
            f"circulant embedding of shape {shape} (spacing {spacing}): the correlation "
            f"reaches so far that the smallest torus that holds it, at least "
            f"{tuple(next_torus)} points, exceeds max_points = {max_points}; no torus could be "
            f"tried. Use "
            f"approximate=True to clip (the lost variance is reported), a smaller grid, or "
            f"method='cholesky'.")
    return NotEmbeddableError(
        f"circulant embedding of shape {shape} (spacing {spacing}) keeps negative "
        f"eigenvalues: most negative {min_rel:.3g} x r(0) (tolerance {tolerance:g}), "
        f"{share:.2g} of the trace, on the largest torus tried, {largest}; tried {tried}; the "
        f"next ({tuple(next_torus)}) exceeds max_points = {max_points}. Use approximate=True "
        f"to clip (the lost variance is reported), a smaller grid, or method='cholesky'.")


def not_valid_error(spacing, where, min_rel, share, tolerance, below):
    """The error for an ACVF whose embedding keeps negative eigenvalues (down to ``min_rel``
    x r(0), ``share`` of the trace) that no larger torus removes: ``where`` says on which
    tori, ``below`` where the ACVF is already below ``tolerance``."""
    return NotEmbeddableError(
        f"the ACVF is not positive definite on a grid of spacing {spacing}: {where} its "
        f"circulant embedding has eigenvalues down to {min_rel:.3g} x r(0) ({share:.2g} "
        f"of the trace) although the ACVF is below {tolerance:g} x r(0) {below}, so no larger "
        f"torus removes them. A valid kernel (eq 5: its PSD is >= 0) is needed.")


STAGNANT_TRIES = 3      # doublings without change after which a larger torus is not tried
STAGNANT_CHANGE = 0.01  # relative change of the most negative eigenvalue and negative share


def _stagnant(tries):
    """True when the last :data:`STAGNANT_TRIES` tries changed neither the most negative
    eigenvalue nor the negative share by more than :data:`STAGNANT_CHANGE` (relative)."""
    if len(tries) <= STAGNANT_TRIES:
        return False
    recent = tries[-STAGNANT_TRIES - 1:]
    return all(abs(b[k] - a[k]) <= STAGNANT_CHANGE * abs(a[k])
               for a, b in zip(recent, recent[1:]) for k in (1, 2))


def wrapped_lags(torus_shape, spacing, rows=slice(None)):
    """Lags of the torus points in (x, y) order, wrapped to [-m/2, m/2) per axis; ``rows``
    (a slice) of the first axis only (only those are computed)."""
    first = np.arange(*rows.indices(torus_shape[0]))
    axes = [np.where(j <= m // 2, j, j - m) * d
            for j, m, d in zip([first] + [np.arange(m) for m in torus_shape[1:]], torus_shape,
                               spacing)]
    mesh = np.meshgrid(*axes, indexing="ij")
    return np.stack(mesh[::-1], axis=-1)


def _fill_rows(values, acvf, spacing, n_rows):
    """``values[:n_rows]`` = the ACVF at the wrapped lags of those rows of the torus
    ``values.shape``, evaluated a block of about ``_BLOCK_POINTS`` points at a time."""
    torus_shape = values.shape
    block_rows = max(1, _BLOCK_POINTS // max(int(np.prod(torus_shape[1:], dtype=np.int64)), 1))
    for start in range(0, n_rows, block_rows):
        rows = slice(start, min(start + block_rows, n_rows))
        values[rows] = acvf(wrapped_lags(torus_shape, spacing, rows))
    if not np.all(np.isfinite(values[:n_rows])):
        raise ValueError("kernel returned non-finite covariances on the embedding torus")


def wrapped_acvf(acvf, torus_shape, spacing):
    """The ACVF at every wrapped lag of the torus (the plain wrap, no taper)."""
    values = np.empty(torus_shape, dtype=np.float64)
    _fill_rows(values, acvf, spacing, torus_shape[0])
    return values


def rounding_level(base, variance):
    """The rounding level of an FFT of the torus ACVF ``base``, relative to r(0): each output
    is computed to about ``eps * log2(M) * sum|c|``, so a negative eigenvalue of that size is
    rounding, not indefiniteness (it matters on large tori of slowly decaying ACVFs)."""
    return (np.finfo(np.float64).eps * max(math.log2(base.size), 1.0)
            * float(np.abs(base).sum()) / variance)


def grid_lag_change(acvf, shape, spacing, torus_shape):
    """``max |c(tau) - r(tau)| / r(0)`` over every lag two grid points have, where c is the tapered
    ACVF on ``torus_shape``: 0 when the embedding leaves R of eq 10 unchanged."""
    base = tapered_acvf(acvf, torus_shape, spacing, shape)
    index = np.ix_(*[np.arange(-(n - 1), n) % m for n, m in zip(shape, torus_shape)])
    lags = np.stack(np.meshgrid(*[np.arange(-(n - 1), n) * d for n, d in zip(shape, spacing)],
                                indexing="ij")[::-1], axis=-1)
    return float(np.max(np.abs(base[index] - acvf(lags))) / base.flat[0])
