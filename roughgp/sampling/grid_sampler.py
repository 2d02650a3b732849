r"""Draws of a latent surface on a regular grid, eq 10: :math:`\mathbf G \sim \mathcal N(0, \mathbf R)`.

``sample_grid`` is the single entry point. Methods:

* ``"cholesky"``: exact. :math:`\mathbf R = \mathbf L\mathbf L^\top` and
  :math:`\mathbf g = \mathbf L\boldsymbol\varepsilon` (the reparameterisation of section 2.2);
  on the CPU, L of a 2-D grid of many rows by block Levinson (the same draw in
  :math:`2 n_y^2 n_x^3` flops, :mod:`~roughgp.sampling.block_levinson`), else dense (time
  :math:`N^3`). The call refuses, before allocating, when N² values would not fit in memory.
* ``"lanczos"``: the paper's approximation (LOVE, Pleiss et al. 2018): GPyTorch's
  ``root_decomposition(method="lanczos")`` with ``rank`` Lanczos iterations gives
  :math:`\mathbf R \approx \mathbf Q\mathbf T\mathbf Q^\top` of rank ``rank``; the draw is
  :math:`\mathbf Q\mathbf T^{1/2}\boldsymbol\varepsilon`; a low rank loses variance (the kept
  share of the trace is reported; GPyTorch's ``rsample()`` takes rank 100 once N > 800).
* ``"circulant"``: exact in O(N log N) by circulant embedding (:mod:`~roughgp.sampling.circulant`),
  an additive kernel (eq 22) as two profiles summed, exactly, in O(N).
* ``"auto"``: the cheapest exact method by a cost model (see :func:`choose_method`).
"""

from __future__ import annotations

import hashlib
import logging
import math
import warnings
from dataclasses import dataclass, field
from typing import Callable

import numpy as np

from roughgp.common.checks import as_generator as _rng
from roughgp.common.checks import check_size
from roughgp.common.device import resolve as resolve_device
from roughgp.common.grid import centred_lags, normalize
from roughgp.common.memory import host_free_bytes
from roughgp.common.threads import blas_threads_for
from roughgp.gp.numpy_kernels import is_additive
from roughgp.sampling import block_levinson, circulant
from roughgp.sampling.kernel_identity import kernel_identity

__all__ = ["sample_grid", "grid_covariance", "covariance_index", "choose_method", "SamplingInfo",
           "acvf_of", "METHODS"]

METHODS = ("auto", "cholesky", "lanczos", "circulant")
_LOG = logging.getLogger(__name__)
_EMBEDDINGS: dict = {}  # the last few circulant embeddings, keyed by kernel state and grid
_CACHE_SIZE = 8  # enough for the four kernels of a two-step honed surface (eq 20)
_CACHE_BYTES = 2 * 2**30  # ... but older entries go once the cache holds more than this
_FACTORS: dict = {}  # the last few dense Cholesky factors (and jitters), keyed by lag table
_FACTOR_BYTES = 2**29  # older factors go once they hold more than this (512 MiB)
_CHOICES, _CHOICES_SIZE = {}, 32  # choose_method's answers by lag table (mirrors share one)
#: The torus search of :func:`choose_method` may cost at most this share of the Cholesky
#: factorisation it would replace (by the cost model): beyond it Cholesky is taken unsearched.
SEARCH_SHARE = 0.25


@dataclass
class SamplingInfo:
    """What ``sample_grid(..., return_info=True)`` did: the method, and its accuracy figures."""

    method: str
    reason: str = ""
    torus_shape: tuple | None = None
    min_eigenvalue: float | None = None
    clipped_fraction: float = 0.0
    kept_trace_fraction: float = 1.0
    jitter: float = 0.0
    cached: bool = False
    details: dict = field(default_factory=dict)

_BYTES = 8  # float64


def acvf_of(kernel, name="kernel") -> Callable:
    """The ACVF of a roughgp kernel (its ``acvf``), or ``kernel`` itself if it is a function
    of lags, checked on each call to return one value per lag (a ``ValueError`` naming
    ``name`` otherwise); ``name``: the argument's name in the error."""
    acvf = getattr(kernel, "acvf", None)
    if callable(acvf):
        return acvf
    if callable(kernel):
        def checked(lags):
            values = kernel(lags)
            full = tuple(getattr(lags, "shape", np.shape(lags)))
            got = tuple(getattr(values, "shape", np.shape(values)))
            if got != full[:-1]:
                raise ValueError(f"{name} must return one covariance per lag: for lags of "
                                 f"shape {full} (..., D) it must return shape {full[:-1]}, "
                                 f"got {got}")
            return values
        return checked
    raise ValueError(f"{name} must be a roughgp StationaryKernel or a function of lags, "
                     f"got {type(kernel).__name__}")


def _available_bytes() -> int:
    return host_free_bytes()


def _lag_table(kernel, shape, spacing) -> np.ndarray:
    """The ACVF on the (2 n - 1)-point lag grid of each axis: every covariance of the grid."""
    table = np.asarray(acvf_of(kernel)(centred_lags(tuple(2 * n - 1 for n in shape), spacing)),
                       dtype=np.float64)
    if not np.all(np.isfinite(table)):
        raise ValueError("kernel returned non-finite covariances on this grid")
    return table


def _table_keys(table, shape, spacing):
    """Keys of a grid's covariance (its lag table): ``(key, mirrored)``, where ``mirrored``
    is the key of the grid's mirror image along x (the table reversed along its last axis;
    None for a profile, whose table is symmetric). A kernel whose table is another's
    mirrored (eq 19's -phi against +phi) is drawn from the other's factor, flipped along x."""
    def key(values):
        digest = hashlib.sha256(np.ascontiguousarray(values).tobytes()).hexdigest()
        return (tuple(shape), tuple(float(d) for d in spacing), digest)
    return key(table), (key(table[..., ::-1]) if len(shape) == 2 else None)


def grid_covariance(kernel, shape, spacing=1.0, *, device=None):
    """The covariance matrix R of eq 10 for the grid points in row-major order, (N, N).

    Uses stationarity: the ACVF is evaluated once on the (2n - 1)-point lag grid of each axis
    and the matrix is gathered from that table, never from an (N, N, D) lag array. With a
    ``device`` (:mod:`roughgp.common.device`) the gather runs there and a float64 tensor on that
    device is returned.
    """
    shape, spacing = normalize(shape, spacing)
    table = _lag_table(kernel, shape, spacing)
    if device is None:
        return _gathered(table, shape)
    index = covariance_index(shape, device)
    import torch

    return torch.as_tensor(table.reshape(-1), device=index.device)[index]


def _gathered(table, shape) -> np.ndarray:
    """The (N, N) covariance of lag ``table``: entry ``((iy, ix), (jy, jx))`` is ``table[jy - iy
    + ny - 1, jx - ix + nx - 1]``, copied from a strided view (4096 points: 0.03-0.05 s, not
    the 0.18-0.7 s of a gather through broadcast index arrays, on the loaded 2-core machine)."""
    table = np.ascontiguousarray(table, dtype=np.float64)
    start = table[tuple(slice(n - 1, None) for n in shape)]  # a view starting at zero lag
    strides = table.strides  # the view reaches back to lag -(n - 1), within the table
    view = np.lib.stride_tricks.as_strided(
        start, shape=(*shape, *shape), strides=(*(-s for s in strides), *strides), writeable=False)
    n_points = int(np.prod(shape))
    return np.ascontiguousarray(view).reshape(n_points, n_points)


def covariance_index(shape, device=None):
    """For a grid of ``shape``: the (N, N) indices of each pair's lag in the flattened
    (2 ny - 1, 2 nx - 1) lag table of :func:`grid_covariance` (numpy, or a torch int64
    tensor on ``device``)."""
    if device is None:
        arange = np.arange
    else:
        import torch

        def arange(n):
            return torch.arange(n, device=device)
    n_points = int(np.prod(shape))
    if len(shape) == 1:
        (n,) = shape
        i = arange(n)
        return i[None, :] - i[:, None] + n - 1
    ny, nx = shape
    iy, ix = arange(ny), arange(nx)
    dy = (iy[None, :] - iy[:, None] + ny - 1)[:, None, :, None]
    dx = (ix[None, :] - ix[:, None] + nx - 1)[None, :, None, :]
    return (dy * (2 * nx - 1) + dx).reshape(n_points, n_points)


def _cholesky_factor(covariance):
    """Lower Cholesky factor and the relative jitter used: the smallest diagonal jitter
    (0, then 1e-12 .. 1e-6 of the mean variance) that makes a numerically semi-definite
    matrix factorisable, with a warning naming the jitter when one was needed. ``covariance``
    is a numpy array or a torch tensor (factorised where it lies)."""
    on_torch = not isinstance(covariance, np.ndarray)
    scale = float(covariance.diagonal().mean())
    for rel in (0.0, 1e-12, 1e-10, 1e-8, 1e-6):
        if on_torch:
            import torch

            a = covariance
            if rel:
                a = covariance.clone()
                a.diagonal().add_(rel * scale)
            factor, failed = torch.linalg.cholesky_ex(a)
            del a
            if int(failed):
                continue
        else:
            try:
                import scipy.linalg  # here: the block-Levinson route needs none of it
                a = covariance + rel * scale * np.eye(len(covariance)) if rel else covariance
                with blas_threads_for(len(a)):
                    factor = scipy.linalg.cholesky(a, lower=True, check_finite=False,
                                                   overwrite_a=a is not covariance)
            except np.linalg.LinAlgError:
                continue
        if rel:
            warnings.warn(f"covariance needed a diagonal jitter of {rel:g} x the mean variance "
                          f"to factorise", stacklevel=4)
        return factor, rel
    raise ValueError("the covariance is not positive semi-definite (Cholesky failed even with "
                     "a jitter of 1e-6 x the mean variance): the kernel is not a valid ACVF "
                     "on this grid")


def _check_dense_memory(shape, method, copies=2, device=None):
    n_points = int(np.prod(shape))
    needed = copies * n_points**2 * _BYTES
    if device is not None:
        from roughgp.common.device import check_memory

        check_memory(needed, device, f"method={method!r} on shape {shape} (a dense "
                                     f"{n_points} x {n_points} covariance)")
        return
    available = _available_bytes()
    if needed > 0.8 * available:
        raise ValueError(f"method={method!r} on shape {shape} needs a dense {n_points} x "
                         f"{n_points} covariance: about {needed / 2**30:.1f} GiB, but only "
                         f"{available / 2**30:.1f} GiB are free; use method='circulant' or a "
                         f"smaller grid")


def _draw_cholesky(kernel, shape, spacing, n_samples, rng, info, device=None):
    _check_dense_memory(shape, "cholesky", copies=2 if device is None else 3, device=device)
    table, mirrored, key = _canonical_table(kernel, shape, spacing)
    if device is not None:
        import torch

        index = covariance_index(shape, device)
        covariance = torch.as_tensor(table.reshape(-1), device=index.device)[index]
        factor, info.jitter = _cholesky_factor(covariance)
        noise = torch.from_numpy(rng.standard_normal((factor.shape[0], n_samples))).to(device)
        samples = (factor @ noise).T.reshape((n_samples, *shape)).cpu().numpy()
    else:
        factor, info.jitter = _cached_factor(table, shape, key, info)
        noise = rng.standard_normal((math.prod(shape), n_samples))
        samples = (factor @ noise).T.reshape((n_samples, *shape))  # L e, dense or by blocks
    return samples[..., ::-1] if mirrored else samples


def _canonical_table(kernel, shape, spacing):
    """The lag table a Cholesky draw factorises, ``(table, mirrored, key)``: the kernel's own, or
    its mirror image along x where that is the canonical one of the two (its covariance along
    the diagonal lag (-(ny - 1), -(nx - 1)) is larger than along the anti-diagonal, as for a
    lay angle in (0, 90) degrees; ties by :func:`_table_keys`). A draw from the mirror image's
    factor, flipped along x, has exactly the kernel's covariance: a kernel and its mirror image
    (eq 19's +-phi) share one factorisation, whatever was drawn before (the same seed, the
    same draw; a positive angle's draws are those of before)."""
    table = _lag_table(kernel, shape, spacing)
    key, mirror = _table_keys(table, shape, spacing)
    if mirror is not None:
        diagonal, anti = table[0, 0], table[0, -1]
        if anti > diagonal or (anti == diagonal and mirror < key):
            return table[..., ::-1], True, mirror
    return table, False, key


def _cached_factor(table, shape, key, info):
    """The Cholesky factor (by block Levinson where worthwhile, else dense) and jitter of lag
    ``table``'s covariance, kept in :data:`_FACTORS` by ``key`` (the newest within
    :data:`_FACTOR_BYTES`): repeated draws and a honed surface's mirrored grounds factorise once."""
    if key in _FACTORS:
        info.cached = True
        return _FACTORS[key]
    factor, jitter = (block_levinson.factorise(table, shape)
                      if block_levinson.worthwhile(shape) else None), 0.0
    if factor is None:
        factor, jitter = _cholesky_factor(_gathered(table, shape))
    if factor.nbytes <= _FACTOR_BYTES:
        _FACTORS[key] = (factor, jitter)
        while sum(f.nbytes for f, _ in _FACTORS.values()) > _FACTOR_BYTES:
            _FACTORS.pop(next(iter(_FACTORS)))
    return factor, jitter


def _draw_lanczos(kernel, shape, spacing, n_samples, rng, info, rank, device=None):
    import torch
    from linear_operator.utils import lanczos

    n_points = int(np.prod(shape))
    if not isinstance(rank, (int, np.integer)) or not 1 <= rank <= n_points:
        raise ValueError(f"rank must be an integer in [1, {n_points}] (the number of grid "
                         f"points), got {rank!r}")
    _check_dense_memory(shape, "lanczos", copies=1 if device is None else 2, device=device)
    device = device or torch.device("cpu")
    covariance = grid_covariance(kernel, shape, spacing, device=device)
    # The steps of linear_operator's RootDecomposition (what GPyTorch's rsample runs beyond
    # max_cholesky_size), with the Lanczos start vector drawn from our seed, not torch's
    # global generator: Q T Q^T ~ R, root = Q V sqrt(D) with T = V D V^T.
    start = torch.from_numpy(rng.standard_normal((n_points, 1))).to(device)
    q_mat, t_mat = lanczos.lanczos_tridiag(covariance.matmul, int(rank), dtype=torch.float64,
                                           device=covariance.device,
                                           matrix_shape=covariance.shape, init_vecs=start)
    # eigh of T directly: linear_operator's lanczos_tridiag_to_diag masks negative Ritz values.
    # Ritz values lie in [lambda_min, lambda_max]: a clearly negative one proves the
    # covariance indefinite, which clamping would hide
    eigenvalues, eigenvectors = torch.linalg.eigh(t_mat)
    # an eigenvector's sign is arbitrary and differs between LAPACK and cuSOLVER: fix it (the
    # largest entry positive) so a seed gives the same draw on every device
    largest = eigenvectors.gather(0, eigenvectors.abs().argmax(0, keepdim=True))
    eigenvectors = eigenvectors * torch.where(largest < 0, -1.0, 1.0)
    if float(eigenvalues.min()) < -1e-8 * float(eigenvalues.max()):
        raise ValueError(f"the covariance is not positive semi-definite (a Lanczos Ritz value "
                         f"is {float(eigenvalues.min()):.3g}, the largest "
                         f"{float(eigenvalues.max()):.3g}): the kernel is not a valid ACVF on "
                         f"this grid")
    root = (q_mat @ eigenvectors) * eigenvalues.clamp_min(0).sqrt().unsqueeze(-2)
    info.kept_trace_fraction = float((root * root).sum() / torch.diagonal(covariance).sum())
    info.details["rank"] = int(root.shape[-1])
    noise = torch.from_numpy(rng.standard_normal((root.shape[-1], n_samples))).to(device)
    return (root @ noise).T.cpu().numpy().reshape((n_samples, *shape))


def _cache_key(kernel, shape, spacing, options):
    identity = kernel_identity(kernel)
    if identity is None:
        return None
    return (identity, shape, tuple(spacing.tolist()), options)


def _embedding(kernel, shape, spacing, info, **options):
    key = _cache_key(kernel, shape, spacing, tuple(sorted(options.items())))
    if key is not None and key in _EMBEDDINGS:
        info.cached = True
        return _EMBEDDINGS[key]
    embedding = circulant.embed(acvf_of(kernel), shape, spacing, **options)
    if key is not None:
        _EMBEDDINGS[key] = embedding
        while len(_EMBEDDINGS) > 1 and (
                len(_EMBEDDINGS) > _CACHE_SIZE
                or sum(e.nbytes for e in _EMBEDDINGS.values()) > _CACHE_BYTES):
            _EMBEDDINGS.pop(next(iter(_EMBEDDINGS)))
    return embedding


def _draw_circulant(kernel, shape, spacing, n_samples, rng, info, approximate, dtype,
                    device=None, truncation="smooth"):
    if is_additive(kernel) and len(shape) == 2:
        # eq 22: G(x, y) = G_x(x) + G_y(y) with independent profiles, exact in O(N)
        ny, nx = shape
        gx = _draw_circulant(kernel.kernel_x, (nx,), spacing[1:], n_samples, rng, info,
                             approximate, dtype, device, truncation)
        gy = _draw_circulant(kernel.kernel_y, (ny,), spacing[:1], n_samples, rng, info,
                             approximate, dtype, device, truncation)
        info.details["additive"] = True
        return gx[:, None, :] + gy[:, :, None]
    embedding = _embedding(kernel, shape, spacing, info, approximate=approximate,
                           truncation=truncation)
    info.torus_shape = embedding.torus_shape
    info.min_eigenvalue = embedding.min_eigenvalue
    info.clipped_fraction = max(info.clipped_fraction, embedding.clipped_fraction)
    if embedding.clipped_fraction > 0:
        warnings.warn(f"approximate circulant embedding: negative eigenvalues holding "
                      f"{embedding.clipped_fraction:.2e} of the variance were clipped",
                      stacklevel=4)
    return circulant.draw(embedding, n_samples, rng, dtype=dtype, device=device)


_FLOPS_PER_SECOND = 2e10  # dense linear algebra on the reference 2-core machine


def choose_method(kernel, shape, spacing=1.0, n_samples=1, *, device=None):
    """The cheapest exact method for this kernel and grid, and why.

    Cost model (seconds, reference machine): Cholesky ``N^3 / 3 + N^2 n`` flops at 2e10 flop/s
    (the block-Levinson factor's :func:`~roughgp.sampling.block_levinson.flops` on the CPU where
    worthwhile), infinite when the dense covariance does not fit in memory; circulant embedding
    ``(2 + ceil(n / 2)) * 5 M log2 M`` flops for the search and the FFTs on the torus of M
    points that :func:`roughgp.sampling.circulant.predict_torus` expects (a few FFTs of a coarse
    copy of the grid; skipped when the dense covariance does not fit in memory).
    The search may cost at most :data:`SEARCH_SHARE` of the Cholesky (same model): on a small
    grid whose correlation length needs a huge torus (figure 3's lambda_a = 500 on 64 x 64
    points: about 2688 x 2688) Cholesky is taken once the search passes that budget. The answer
    is kept for the kernel's lag table, which its mirror image (eq 19's -phi) shares. An
    additive kernel (eq 22) always goes to the O(N) circulant route. ``device``: not None, the
    dense factor's cost (a device factorises densely)."""
    shape, spacing = normalize(shape, spacing)
    if is_additive(kernel) and len(shape) == 2:
        return "circulant", "additive kernel (eq 22): two exact profiles, O(N)"
    n_points = int(np.prod(shape))
    dense_bytes = 2 * n_points**2 * _BYTES
    if dense_bytes > 0.8 * _available_bytes():  # no need to predict the torus (a search)
        return "circulant", "circulant (the dense covariance of Cholesky is out of memory)"
    by_blocks = device is None and block_levinson.worthwhile(shape)  # as _cached_factor does
    factor_flops = block_levinson.flops(shape) if by_blocks else n_points**3 / 3
    cholesky_cost = (factor_flops + n_points**2 * n_samples) / _FLOPS_PER_SECOND
    key, mirror = _table_keys(_lag_table(kernel, shape, spacing), shape, spacing)
    key = (min(key, mirror or key), n_samples, by_blocks)
    if key not in _CHOICES:
        _CHOICES[key] = _cheaper(kernel, shape, spacing, n_samples, cholesky_cost)
        while len(_CHOICES) > _CHOICES_SIZE:
            _CHOICES.pop(next(iter(_CHOICES)))
    return _CHOICES[key]


def _fft_cost(points: int, passes: float) -> float:
    """Seconds of ``passes`` FFTs over ``points`` (the cost model of :func:`choose_method`)."""
    return passes * 5 * points * max(math.log2(points), 1) / (_FLOPS_PER_SECOND / 10)


def _cheaper(kernel, shape, spacing, n_samples, cholesky_cost):
    """:func:`choose_method`'s comparison once Cholesky fits in memory."""
    passes = 2 + math.ceil(n_samples / 2)
    least = circulant.minimal_torus(shape)
    smallest = _fft_cost(int(np.prod(least)), passes)
    if cholesky_cost <= smallest:  # even the least torus costs more
        return "cholesky", (f"Cholesky ~{cholesky_cost:.2g} s vs circulant ~{smallest:.2g} s "
                            f"or more (the smallest torus, {least})")
    budget = SEARCH_SHARE * cholesky_cost
    cap = 2**40  # the largest torus the search may try: its two passes within the budget
    for _ in range(8):
        cap = max(int(budget * (_FLOPS_PER_SECOND / 10) / (2 * 5 * max(math.log2(cap), 1))), 1)
    try:
        torus = circulant.predict_torus(acvf_of(kernel), shape, spacing,
                                        max_points=min(cap, 2**27))
    except circulant.NotEmbeddableError:
        return "cholesky", (f"Cholesky ~{cholesky_cost:.2g} s; circulant embedding needs a "
                            f"torus of more than {cap:.3g} points, where searching it would "
                            f"cost more than {SEARCH_SHARE:g} of the Cholesky")
    circulant_cost = _fft_cost(int(np.prod(torus)), passes)
    if cholesky_cost <= circulant_cost:
        return "cholesky", (f"Cholesky ~{cholesky_cost:.2g} s vs circulant ~{circulant_cost:.2g} s "
                            f"(torus about {torus})")
    return "circulant", (f"circulant ~{circulant_cost:.2g} s (torus about {torus}) vs Cholesky "
                         f"~{cholesky_cost:.2g} s")


def sample_grid(kernel, shape, *, spacing=1.0, n_samples=1, method="auto", seed=None,
                rank=100, approximate=False, dtype=np.float64, device=None, return_info=False,
                truncation="smooth"):
    """Draw ``n_samples`` latent surfaces G ~ N(0, R) (eq 10) on a regular grid.

    Args:
        kernel: a :class:`roughgp.gp.kernels.StationaryKernel` (its ``acvf`` is used) or a
            function of lags of shape (..., D) returning the ACVF.
        shape: ``(n,)`` for a profile or ``(ny, nx)`` for a surface (array order).
        spacing: grid spacing, scalar or per axis in array order.
        n_samples: number of independent draws (>= 1).
        method: ``"auto"``, ``"cholesky"``, ``"lanczos"`` or ``"circulant"`` (module docstring).
        seed: int, None or ``numpy.random.Generator``; the same seed gives the same array.
        rank: Lanczos iterations for ``method="lanczos"``.
        approximate: circulant only: clip negative eigenvalues of a smaller torus (the clipped
            share of the variance is reported and warned about) instead of growing it.
        truncation: circulant only: ``"smooth"`` tapers the ACVF beyond the grid's lags (the
            grid covariance unchanged, a torus near (2n)^D), ``"none"`` wraps it plainly
            (:func:`roughgp.sampling.circulant.embed`).
        dtype: of the result; ``numpy.float32`` also runs circulant FFTs in single precision
            (half the memory). Dense methods always compute in float64.
        device: None (numpy) or a torch device such as ``"cuda"`` (:mod:`roughgp.common.device`):
            the FFTs, factorisations and products run there. Circulant draws then take their
            noise from a torch generator on the device (seeded from ``seed``: the same seed
            gives the same array on the same kind of device, other numbers than numpy's);
            Cholesky and Lanczos draws take it from numpy and match ``device=None`` to
            rounding. The embedding search of the circulant method stays on the CPU (it is
            cached).
        return_info: also return a :class:`SamplingInfo`.

    Returns:
        numpy array of shape ``(n_samples, *shape)`` (and the info when asked).
    """
    shape, spacing = normalize(shape, spacing)
    if not isinstance(n_samples, (int, np.integer)) or n_samples < 1:
        raise ValueError(f"n_samples must be an integer >= 1, got {n_samples!r}")
    check_size(f"shape = {tuple(shape)} with n_samples = {int(n_samples)}",
               int(n_samples) * math.prod(shape))
    if method not in METHODS:
        raise ValueError(f"method must be one of {METHODS}, got {method!r}")
    try:
        valid_dtype = np.dtype(dtype) in (np.float32, np.float64)
    except TypeError:
        valid_dtype = False
    if not valid_dtype:
        raise ValueError(f"dtype must be numpy.float32 or numpy.float64, got {dtype!r}")
    dtype = np.dtype(dtype)
    acvf_of(kernel)
    device = resolve_device(device)
    rng = _rng(seed)
    n_samples = int(n_samples)
    reason = "requested"
    if method == "auto":
        method, reason = choose_method(kernel, shape, spacing, n_samples, device=device)
        _LOG.info("sample_grid chose method=%r: %s", method, reason)
    info = SamplingInfo(method=method, reason=reason)
    if method == "cholesky":
        samples = _draw_cholesky(kernel, shape, spacing, n_samples, rng, info, device)
    elif method == "lanczos":
        samples = _draw_lanczos(kernel, shape, spacing, n_samples, rng, info, rank, device)
    else:
        samples = _draw_circulant(kernel, shape, spacing, n_samples, rng, info, approximate,
                                  dtype, device, truncation)
    samples = samples.astype(dtype, copy=False)  # dense methods compute in float64
    return (samples, info) if return_info else samples
