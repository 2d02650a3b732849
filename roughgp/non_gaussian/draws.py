r"""Non-Gaussian surfaces: a pre-distorted GP draw (eq 10) through a Johnson transform.

:func:`non_gaussian_surface` draws X with the pre-distorted ACVF (circulant embedding, clipped
and reported where that ACVF is not positive definite on the grid) and returns
:math:`Z = T(X)` with the target skewness, kurtosis and ACVF.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass

import numpy as np

from roughgp.common.checks import as_generator as _rng
from roughgp.non_gaussian.hermite import (
    CorrelationMap,
    PredistortedACVF,
    correlation_map,
    zero_lag_value,
)
from roughgp.non_gaussian.johnson import Johnson, johnson_for
from roughgp.sampling import circulant
from roughgp.sampling.grid_sampler import SamplingInfo, acvf_of, sample_grid

# --------------------------------------------------------------------------- the surface


@dataclass
class NonGaussianInfo:
    """What :func:`non_gaussian_surface` did.

    Attributes:
        johnson, correlation_map: the transform and its g.
        sampling: the :class:`roughgp.sampling.SamplingInfo` of the Gaussian input X.
        predistortion: whether X had the pre-distorted ACVF (else the target's correlation).
        variance: r(0) of the target (the heights' variance).
        clipped_fraction: the share of the embedding's trace clipped (0: exact draw).
        unattainable_fraction: share of the evaluated lags whose target correlation is below
            g(-1) (the output correlation is g(-1) there instead).
        min_target_correlation: the lowest r(tau)/r(0) among the evaluated lags.
    """

    johnson: Johnson
    correlation_map: CorrelationMap
    sampling: SamplingInfo
    predistortion: bool
    variance: float
    clipped_fraction: float
    unattainable_fraction: float
    min_target_correlation: float

    @property
    def attainable_range(self):
        """[g(-1), 1]: the output correlations a Gaussian input can give."""
        return (self.correlation_map.lower, 1.0)


_INPUTS: dict = {}  # the last few pre-distorted ACVFs by kernel, map and grid: a check draws
_INPUTS_SIZE = 8    # 19-99 times from one model, and the embedding search is the costly part
_INPUTS_BYTES = 2**30  # ... but older entries go once their clipped embeddings hold more


def _input_for(kernel, cmap, shape, spacing, method):
    """The pre-distorted ACVF of ``kernel`` for this grid, the same object for the same kernel
    state, map and grid (so its counts of unattainable lags go with the embedding that
    :func:`~roughgp.sampling.sample_grid` caches), and a slot for its clipped embedding."""
    fresh = PredistortedACVF(kernel, cmap, unattainable="clip")
    identity = fresh.cache_key()
    if identity is None:  # a plain function: nothing to tell whether it changed
        return [fresh, None]
    key = (identity, tuple(shape), tuple(np.asarray(spacing).tolist()), method)
    if key not in _INPUTS:
        _INPUTS[key] = [fresh, None]
    _forget_old()
    return _INPUTS[key]


def _forget_old():
    """Drop the oldest entries beyond :data:`_INPUTS_SIZE` or :data:`_INPUTS_BYTES`."""
    def held():
        return sum(slot[1][1].nbytes for slot in _INPUTS.values() if slot[1] is not None)
    while len(_INPUTS) > 1 and (len(_INPUTS) > _INPUTS_SIZE or held() > _INPUTS_BYTES):
        _INPUTS.pop(next(iter(_INPUTS)))


def _clipped_embedding(acvf, shape, spacing, max_clipped_fraction):
    """The approximate circulant embedding of a non-positive-definite pre-distorted ACVF:
    negative eigenvalues clipped (at most ``max_clipped_fraction`` of the trace)."""
    try:
        return circulant.embed(acvf, shape, spacing, approximate=True,
                               max_clipped_fraction=max_clipped_fraction)
    except circulant.NotEmbeddableError as again:
        unattainable = (f" {acvf.unattainable_fraction:.1%} of the lags had target "
                        f"correlations below g(-1) = {acvf.cmap.lower:.3g} (down to "
                        f"{acvf.min_target:.3g}), set to g(-1)." if acvf.n_unattainable else "")
        raise ValueError(f"the pre-distorted ACVF is not positive definite on this grid and "
                         f"clipping its circulant embedding would remove more than "
                         f"max_clipped_fraction={max_clipped_fraction!r} of the trace: this "
                         f"target ACVF and height distribution cannot be combined.{unattainable}"
                         f" ({again})") from None


def _draw_clipped(embedding, n_samples, seed):
    """X drawn from a clipped embedding, rescaled to unit variance so that the marginal
    moments stay exact."""
    variance = float(np.sum(embedding.scale.astype(np.float64) ** 2))  # clipped torus' r_X(0)
    x = circulant.draw(embedding, n_samples, _rng(seed)) / math.sqrt(variance)
    info = SamplingInfo(method="circulant", reason="approximate: pre-distorted ACVF not "
                        "non-negative definite, negative eigenvalues clipped",
                        torus_shape=embedding.torus_shape, min_eigenvalue=embedding.min_eigenvalue,
                        clipped_fraction=embedding.clipped_fraction,
                        details={"input_variance_before_rescaling": variance})
    return x, info


def non_gaussian_surface(kernel, shape, *, skewness, kurtosis, spacing=1.0, seed=None,
                         method="circulant", n_samples=None, predistortion=True, n_terms=None,
                         max_clipped_fraction=0.01):
    r"""A surface with the target ACVF r of ``kernel`` and Johnson heights of the given
    skewness and kurtosis: :math:`Z = T(X)`, X a standard GP with the pre-distorted ACVF
    :math:`g^{-1}(r/r(0))`. The heights have variance r(0), zero mean and the target skewness
    and kurtosis exactly (marginally; with ``method="lanczos"`` a low rank loses variance, see
    ``info.sampling.kept_trace_fraction``); the ACVF is r wherever r(tau)/r(0) >= g(-1) and the
    pre-distorted ACVF is positive definite on the grid (else see ``info.clipped_fraction``).

    This is eq 9 with a deterministic noise model :math:`p(z \mid g) = \delta(z - T(g))` (eq 8)
    on a pre-distorted GP: the non-Gaussian surfaces of the paper's conclusion.

    Args:
        kernel: a roughgp kernel or a function of lags (..., D) giving the target ACVF r.
        shape: ``(n,)`` or ``(ny, nx)``; ``spacing`` as in :func:`roughgp.sampling.sample_grid`.
        skewness, kurtosis: Ssk and Sku (Pearson's kurtosis, 3 for Gaussian heights);
            kurtosis > skewness**2 + 1.
        seed: int, None or ``numpy.random.Generator``: the same seed gives the same surface.
        method: of ``sample_grid`` (``"circulant"``: exact in O(N log N); if the pre-distorted
            ACVF's embedding has negative eigenvalues that no torus removes, the draw is
            repeated with ``approximate=True``, with a warning, and the clipped share is
            reported).
        n_samples: None for one surface of ``shape``, or an int for ``(n_samples, *shape)``.
        predistortion: False draws X with the target correlation itself (for comparison: the
            output ACVF is then r(0) g(r/r(0)), not r).
        n_terms: Hermite terms of g (default: adaptive, see :func:`correlation_map`).
        max_clipped_fraction: the largest share of the embedding's trace that may be clipped
            when the pre-distorted ACVF is not non-negative definite (else ValueError).

    Returns:
        ``(z, info)`` with info a :class:`NonGaussianInfo`.
    """
    from roughgp.common.grid import normalize

    shape, spacing = normalize(shape, spacing)
    acvf = acvf_of(kernel)
    variance = zero_lag_value(acvf, len(shape))
    johnson = johnson_for(skewness, kurtosis, variance)
    cmap = correlation_map(johnson, n_terms)
    slot = None
    if predistortion:
        slot = _input_for(kernel, cmap, shape, spacing, method)
        input_acvf = slot[0]
    else:
        def input_acvf(lags):
            return np.asarray(acvf(lags), dtype=np.float64) / variance
    count = 1 if n_samples is None else n_samples
    clipped = slot[1] if slot is not None else None
    if clipped is None or clipped[0] != max_clipped_fraction:
        try:
            x, sampling = sample_grid(input_acvf, shape, spacing=spacing, n_samples=count,
                                      method=method, seed=seed, return_info=True)
            clipped = None
        except circulant.NotEmbeddableError:
            if not predistortion or method not in ("circulant", "auto"):
                raise
            clipped = (max_clipped_fraction, _clipped_embedding(input_acvf, shape, spacing,
                                                                max_clipped_fraction))
            slot[1] = clipped
            _forget_old()
    if clipped is not None:
        x, sampling = _draw_clipped(clipped[1], count, seed)
        warnings.warn(f"the pre-distorted ACVF is not non-negative definite on this grid: its "
                      f"circulant embedding's negative eigenvalues, {sampling.clipped_fraction:.2e}"
                      f" of the trace, were clipped (and X rescaled to unit variance), so the "
                      f"surface's ACVF only approximates the target", stacklevel=2)
    z = johnson.transform(x)
    if n_samples is None:
        z = z[0]
    unattainable = input_acvf.unattainable_fraction if predistortion else 0.0
    min_target = input_acvf.min_target if predistortion else math.nan
    if unattainable > 0:
        warnings.warn(f"target correlations down to {min_target:.3g} are below g(-1) = "
                      f"{cmap.lower:.3g} at {unattainable:.2%} of the lags: the surface has "
                      f"correlation g(-1) there", stacklevel=2)
    info = NonGaussianInfo(johnson, cmap, sampling, bool(predistortion), variance,
                           sampling.clipped_fraction, unattainable, min_target)
    return z, info
