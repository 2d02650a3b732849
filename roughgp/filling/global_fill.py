r"""Filling unmeasured points of a height map with the GP posterior (beyond the paper).

The paper's conclusion (ref [48]) notes that optical instruments leave non-measured or
spurious points at steep slopes and that the GP model can interpolate them. Given a height
map ``z[iy, ix]`` on a regular grid with NaNs (or a ``mask`` of points to treat as missing),
a stationary kernel and the noise variance :math:`\sigma^2` of eq 8, :func:`fill_gaps`
returns the posterior mean of the latent surface (eq 11 restricted to the grid) and a Monte
Carlo estimate of its posterior standard deviation, without ever forming a dense matrix.

Method
------
* **Mean.** With ``P`` the selection of the observed points, the conjugate-gradient (CG)
  solve of :math:`(P K P^\top + \sigma^2 I)\,\alpha = y_o - \bar y` and the posterior mean
  :math:`\bar y + K P^\top \alpha`. ``bar y`` is the mean of the observed heights (a constant
  mean, removed and added back). The product with the grid covariance ``K`` (block Toeplitz)
  is *exact*: the grid is embedded in a torus of at least ``2 n`` points per axis, the ACVF is
  wrapped periodically on it, and ``K v`` is the grid part of the circular convolution of the
  zero-padded ``v`` with the wrapped ACVF (two FFTs). No non-negative embedding is needed
  for this product.
* **Preconditioner** (``preconditioner="circulant"``, the default): the observed part of the
  inverse of the torus operator, :math:`P\,\mathcal F^{-1}(\max(\Lambda, 0) + \sigma^2)^{-1}
  \mathcal F\,P^\top`, symmetric positive definite and one matvec's cost. It is exact when
  nothing is missing and stays good for a moderate missing share; ``None`` runs plain CG
  (the Jacobi preconditioner of a stationary kernel is a constant, hence useless).
* **Standard deviation** by pathwise conditioning (Matheron's rule): for each of
  ``n_samples`` seeded prior draws ``f`` (exact circulant sampler of
  :func:`roughgp.sampling.sample_grid`; where the kernel's exact torus is too large, the
  clipped embedding of a smaller one, its lost variance reported as
  ``prior_clipped_fraction``) and noise ``e`` on the observed points,
  :math:`d = f - K P^\top (P K P^\top + \sigma^2 I)^{-1}(P f + e)` is a draw of the posterior
  error ``g - E[g | y]``, so ``sd = sqrt(mean(d**2))`` over the draws (``n_samples`` degrees
  of freedom: its relative sampling error is about ``1 / sqrt(2 n_samples)``). The draws'
  solves run together, one batched CG, and stop at a looser ``sample_tol`` (1e-3) than the
  mean's ``tol`` (1e-6); they run in single precision (``sample_dtype``): at that tolerance
  float32 changes the sd by far less than its Monte Carlo error (on a 256 x 256 test, by at
  most 0.005 where the sd is 0.3 to 3) and takes about 0.6 times the float64 time.

The ``sd`` is that of the latent surface ``g``; the spread of a new *measurement* at a point is
``sqrt(sd**2 + noise_variance)``. Hyperparameters are inputs: this module does not fit them.
"""

from __future__ import annotations

import time
import warnings
from dataclasses import dataclass

import numpy as np
import scipy.fft

from roughgp.common.checks import (
    as_generator,
    check_integer,
    check_nonnegative,
    check_positive,
    check_size,
)
from roughgp.common.device import resolve as resolve_device
from roughgp.common.grid import normalize
from roughgp.sampling.circulant import NotEmbeddableError, wrapped_lags
from roughgp.sampling.grid_sampler import acvf_of, sample_grid

__all__ = ["GapFill", "ToeplitzOperator", "fill_gaps", "conjugate_gradients", "missing_map"]

PRECONDITIONERS = ("circulant", None)
_SINGLE_TOL = 1e-5  # the tightest relative residual asked of a float32 CG solve


@dataclass(frozen=True)
class GapFill:
    """The result of :func:`fill_gaps`.

    Attributes:
        mean: posterior mean of the latent surface on the whole grid, ``(ny, nx)``.
        sd: posterior standard deviation of the latent surface (Monte Carlo, ``n_samples``
            pathwise draws; zeros when ``n_samples == 0``), ``(ny, nx)``.
        missing: boolean map of the points treated as missing.
        filled: the input with the missing points replaced by ``mean``.
        iterations: CG iterations of the mean's solve.
        sample_iterations: CG iterations of the slowest draw's solve (0 without draws).
        converged: every solve reached its tolerance (``tol``, ``sample_tol``).
        seconds: wall time of the call.
        prior_clipped_fraction: 0 when the prior draws are exact; else the share of the
            prior variance lost by the clipped circulant embedding they were drawn from (the
            exact torus of the kernel was too large), so ``sd`` is that much too small.
    """

    mean: np.ndarray
    sd: np.ndarray
    missing: np.ndarray
    filled: np.ndarray
    iterations: int
    sample_iterations: int
    converged: bool
    seconds: float
    prior_clipped_fraction: float = 0.0


class ToeplitzOperator:
    """Exact products with the (block-)Toeplitz grid covariance via a periodic embedding.

    ``matvec(v)`` for ``v`` of shape ``(..., ny, nx)`` returns ``K v`` on the grid, where ``K``
    is the covariance of the grid points; the torus has ``next_fast_len(2 n)`` points per axis.
    With a ``device`` (a ``torch.device``, :mod:`roughgp.common.device`) the spectrum lives there and
    ``matvec`` takes and returns torch tensors on it.
    """

    def __init__(self, kernel, shape, spacing=1.0, device=None):
        shape, spacing = normalize(shape, spacing)
        if len(shape) != 2:
            raise ValueError(f"shape must be (ny, nx), got {shape}")
        self.shape = tuple(int(n) for n in shape)
        self.torus = tuple(scipy.fft.next_fast_len(2 * n, real=True) for n in self.shape)
        base = np.asarray(acvf_of(kernel)(wrapped_lags(self.torus, spacing)), dtype=np.float64)
        if base.shape != self.torus or not np.all(np.isfinite(base)):
            raise ValueError("kernel returned non-finite covariances on the embedding torus")
        self.variance = float(base[0, 0])
        if self.variance <= 0:
            raise ValueError(f"the kernel's variance (ACVF at lag 0) must be > 0, "
                             f"got {self.variance}")
        self.device = device
        if device is None:
            self.spectrum = scipy.fft.rfft2(base, workers=-1)  # exact circular convolution
        else:
            import torch

            self.spectrum = torch.fft.rfft2(torch.as_tensor(base, device=device))

    def _apply(self, values, multiplier):
        """The grid part of the circular convolution of ``values`` (zero-padded to the torus)
        with the kernel whose spectrum is ``multiplier``; in single precision for float32
        ``values``."""
        ny, nx = self.shape
        if self.device is not None:
            import torch

            if values.dtype == torch.float32:
                multiplier = multiplier.to(torch.complex64 if multiplier.is_complex()
                                           else torch.float32)
            spec = torch.fft.rfft2(values, s=self.torus) * multiplier
            return torch.fft.irfft2(spec, s=self.torus)[..., :ny, :nx]
        if values.dtype == np.float32:
            multiplier = multiplier.astype(np.complex64 if np.iscomplexobj(multiplier)
                                           else np.float32)
        spec = scipy.fft.rfft2(values, s=self.torus, axes=(-2, -1), workers=-1)
        spec *= multiplier
        return scipy.fft.irfft2(spec, s=self.torus, axes=(-2, -1), workers=-1)[..., :ny, :nx]

    def matvec(self, values):
        return self._apply(values, self.spectrum)

    def inverse_torus(self, values, noise_variance):
        """``(C + s2 I)^{-1}`` of the torus operator (eigenvalues clipped at 0), grid part."""
        denominator = self.spectrum.real.clip(0.0, None) + noise_variance
        return self._apply(values, 1.0 / denominator)


def conjugate_gradients(matvec, rhs, *, precondition=None, tol=1e-6, max_iter=1000):
    """Batched (preconditioned) CG: solves ``A x_k = b_k`` for every ``b_k = rhs[k]``.

    ``matvec`` and ``precondition`` act on stacks of right-hand sides (first axis), shaped
    like ``rhs[active]``; only the systems not yet converged are passed on. ``tol`` is a
    scalar or one value per right-hand side; system k stops when ``||r_k|| <= tol_k ||b_k||``.
    ``rhs`` is a numpy array or a torch tensor (on any device: the stacks stay there, the
    per-system scalars live on the host).

    Returns:
        ``(x, iterations, converged)``: ``x`` like ``rhs``; ``iterations`` per right-hand
        side, ``converged`` a boolean per right-hand side (numpy).
    """
    precondition = precondition or (lambda r: r)
    on_numpy = isinstance(rhs, np.ndarray)

    def per_system(values):  # numpy vector on the host -> shaped to scale a stack
        values = values.reshape((-1,) + (1,) * (rhs.ndim - 1))
        return values.astype(rhs.dtype) if on_numpy else rhs.new_tensor(values)

    def sums(a, b):  # per-system inner products, on the host
        out = (a * b).sum(axis=axes)
        return out if on_numpy else out.cpu().numpy()

    n_rhs = rhs.shape[0]
    axes = tuple(range(1, rhs.ndim))
    x = rhs * 0
    r = rhs * 1
    bnorm = np.sqrt(sums(rhs, rhs))
    target = np.broadcast_to(np.asarray(tol, dtype=np.float64), (n_rhs,)) * np.where(
        bnorm > 0, bnorm, 1.0)
    done = np.sqrt(sums(r, r)) <= target
    iterations = np.zeros(n_rhs, dtype=int)
    z = precondition(r)
    p = z * 1
    rz = sums(r, z)
    while True:
        active = np.flatnonzero(~done & (iterations < max_iter))
        if active.size == 0:
            break
        iterations[active] += 1
        pa = p[active]
        ap = matvec(pa)
        pap = sums(pa, ap)
        alpha = per_system(rz[active] / np.where(pap > 0, pap, 1.0))
        x[active] += alpha * pa
        r[active] -= alpha * ap
        ra = r[active]
        done[active] = np.sqrt(sums(ra, ra)) <= target[active]
        za = precondition(ra)
        rz_new = sums(ra, za)
        beta = per_system(rz_new / np.where(rz[active] > 0, rz[active], 1.0))
        p[active] = za + beta * pa
        rz[active] = rz_new
    return x, iterations, done


def missing_map(z, mask, *, allow_complete=False):
    """``(z as float64, missing)``: the NaN points of the height map ``z`` or-ed with a boolean
    ``mask`` of points to treat as missing, each checked (a 2-D map of at least 2 x 2 points, no
    inf, a mask of z's shape and dtype bool, at least one observed point and, unless
    ``allow_complete``, at least one missing point); a ValueError says what is wrong."""
    z = np.asarray(z, dtype=np.float64)
    if z.ndim != 2 or min(z.shape) < 2:
        raise ValueError(f"z must be a 2-D height map z[iy, ix] with at least 2 points per "
                         f"axis, got shape {z.shape}")
    if np.any(np.isinf(z)):
        raise ValueError("z must not hold inf; mark unmeasured points with NaN or in mask")
    missing = np.isnan(z)
    if mask is not None:
        mask = np.asarray(mask)
        if mask.dtype != bool:
            raise ValueError(f"mask must be a boolean array (True: treat as missing), "
                             f"got dtype {mask.dtype}")
        if mask.shape != z.shape:
            raise ValueError(f"mask must have the shape of z {z.shape}, got {mask.shape}")
        missing = missing | mask
    if np.all(missing):
        raise ValueError("z has no valid (observed) point: all are NaN or masked")
    if not allow_complete and not np.any(missing):
        raise ValueError("z has no missing point: no NaN and nothing masked, nothing to fill")
    return z, missing


#: Arrays of the pathwise draws' size that fill_gaps holds at once (prior, noise, the CG's).
_DRAW_COPIES = 8


def _prior_draws(kernel, shape, spacing, n_samples, rng, device):
    """The pathwise prior draws: exact circulant embedding, or, when the kernel's exact torus
    is too large, the clipped embedding of a smaller one (its lost share of the variance is
    returned, not hidden)."""
    try:
        return sample_grid(kernel, shape, spacing=spacing, n_samples=n_samples,
                           method="circulant", seed=rng, device=device), 0.0
    except NotEmbeddableError:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", UserWarning)  # the share is returned instead
            draws, info = sample_grid(kernel, shape, spacing=spacing, n_samples=n_samples,
                                      method="circulant", seed=rng, device=device,
                                      approximate=True, return_info=True)
        return draws, float(info.clipped_fraction)


def fill_gaps(z, kernel, *, noise_variance, spacing=1.0, mask=None, n_samples=16, seed=None,
              tol=1e-6, sample_tol=1e-3, max_iter=1000,
              preconditioner="circulant", sample_dtype=np.float32, device=None) -> GapFill:
    """Fill the NaN (and ``mask``-ed) points of a height map with the GP posterior mean.

    Args:
        z: height map ``z[iy, ix]`` on a regular grid, NaN where not measured.
        kernel: a stationary 2-D kernel of :mod:`roughgp.gp.kernels` (e.g. eq 18's
            ``RotatedExponentialKernel``) or a function of lags ``(..., 2)`` in (x, y) order;
            its hyperparameters are taken as known.
        noise_variance: :math:`\\sigma^2 \\ge 0` of eq 8 (0 only if the observed part of the
            grid covariance is well conditioned).
        spacing: grid spacing, scalar or ``(dy, dx)``, in the kernel's length unit.
        mask: optional boolean array of the shape of ``z``; True marks points to treat as
            missing (e.g. spurious outliers) in addition to the NaNs.
        n_samples: pathwise posterior draws for ``sd`` (0: no sd, zeros returned).
        seed: int, None or ``numpy.random.Generator`` for the prior draws.
        tol: relative residual of the CG solve of the mean.
        sample_tol: relative residual of the CG solves of the ``n_samples`` draws (looser by
            default: ``sd`` carries a Monte Carlo error of ~``1/sqrt(2 n_samples)`` anyway).
        max_iter: CG iteration cap; ``converged`` is False when it is reached.
        preconditioner: ``"circulant"`` (module docstring) or ``None``.
        sample_dtype: ``numpy.float32`` (default) or ``numpy.float64``: the precision of the
            draws' solves (the mean's is always float64). Single precision is ample for their
            ``sample_tol`` of 1e-3 and about 1.6 times faster (module docstring); it needs
            ``sample_tol >= 1e-5``.
        device: None (numpy and scipy) or a torch device such as ``"cuda"``
            (:mod:`roughgp.common.device`): the FFT products and the CG iterations run there (the
            prior draws too; their noise then comes from a device generator).

    Returns:
        :class:`GapFill`.
    """
    start = time.perf_counter()
    z, missing = missing_map(z, mask)
    check_nonnegative("noise_variance", noise_variance)
    noise_variance = float(noise_variance)
    n_samples = check_integer("n_samples", n_samples, 0)
    check_size(f"n_samples = {n_samples} pathwise draws of shape {z.shape}", n_samples * z.size,
               copies=_DRAW_COPIES)
    check_positive("tol", tol)
    check_positive("sample_tol", sample_tol)
    max_iter = check_integer("max_iter", max_iter, 1)
    if sample_dtype not in (np.float32, np.float64):
        raise ValueError(f"sample_dtype must be numpy.float32 or numpy.float64, "
                         f"got {sample_dtype!r}")
    if sample_dtype == np.float32 and n_samples and sample_tol < _SINGLE_TOL:
        raise ValueError(f"sample_tol must be >= {_SINGLE_TOL:g} with sample_dtype float32 "
                         f"(single precision cannot resolve less), got {sample_tol!r}; use "
                         f"sample_dtype=numpy.float64 for a tighter tolerance")
    if preconditioner not in PRECONDITIONERS:
        raise ValueError(f"preconditioner must be one of {PRECONDITIONERS}, "
                         f"got {preconditioner!r}")
    device = resolve_device(device)
    rng = as_generator(seed)
    shape, spacing = normalize(z.shape, spacing)
    operator = ToeplitzOperator(kernel, shape, spacing, device)
    observed = ~missing
    weight = observed.astype(np.float64)

    offset = float(np.mean(z[observed]))
    data = np.where(observed, z - offset, 0.0)[None]
    prior, clipped = None, 0.0
    if n_samples:
        prior, clipped = _prior_draws(kernel, shape, spacing, n_samples, rng, device)
        noise = np.sqrt(noise_variance) * rng.standard_normal((n_samples, *shape))
        draws = (-(prior + noise) * weight).astype(sample_dtype)
    if device is not None:
        import torch

        data, weight = (torch.as_tensor(a, device=device) for a in (data, weight))
        if n_samples:
            draws = torch.as_tensor(draws, device=device)

    def solve(rhs, tolerance):
        """CG for (P K P^T + s2 I) alpha = rhs, in the precision of rhs; returns K alpha."""
        w = weight.to(rhs.dtype) if device is not None else weight.astype(rhs.dtype)

        def matvec(v):  # (P K P^T + s2 I) v, v zero off the observed points
            return operator.matvec(v) * w + noise_variance * v

        precondition = None
        if preconditioner == "circulant":
            def precondition(r):
                return operator.inverse_torus(r, noise_variance) * w

        alpha, its, converged = conjugate_gradients(matvec, rhs, precondition=precondition,
                                                    tol=tolerance, max_iter=max_iter)
        product = operator.matvec(alpha)
        product = product.cpu().numpy() if device is not None else product
        return product.astype(np.float64), its, converged

    correction, iterations, done = solve(data, tol)
    sample_iterations = 0
    if n_samples:
        sample_correction, its, converged = solve(draws, sample_tol)
        sample_iterations = int(its.max())
        done = np.concatenate((done, converged))
    mean = correction[0] + offset
    if n_samples:
        errors = prior + sample_correction
        sd = np.sqrt(np.mean(errors**2, axis=0))
    else:
        sd = np.zeros(shape)
    if not (np.all(np.isfinite(mean)) and np.all(np.isfinite(sd))):
        raise FloatingPointError("non-finite posterior: check noise_variance and the kernel")
    filled = np.where(missing, mean, z)
    return GapFill(mean=mean, sd=sd, missing=missing, filled=filled, iterations=int(iterations[0]),
                   sample_iterations=sample_iterations, converged=bool(np.all(done)),
                   seconds=time.perf_counter() - start, prior_clipped_fraction=clipped)
