r"""A non-stationary eq 18 surface: local hyperparameters that vary smoothly over the map.

The paper's future work (section 4; section 2.3's linear-process view; refs [37, 47]). Here
:math:`\sigma_k^2, \lambda_a, \lambda_b, \phi` of eq 18 are functions of the position x, and
S(x) = T_phi^T diag(lambda_a^2, lambda_b^2) T_phi is the local matrix whose inverse is eq 18's
quadratic form, ``q = tau^T S^-1 tau = |Lambda^-1 T_phi tau|^2``.

* :func:`paciorek_covariance`: the closed form of Paciorek & Schervish (2006, theorem 1),
  :math:`C(x, x') = s(x) s(x') |S|^{1/4} |S'|^{1/4} |(S + S')/2|^{-1/2} \rho(Q)`,
  :math:`Q = (x - x')^\top ((S + S')/2)^{-1} (x - x')`, with
  :math:`\rho(Q) = e^{-\sqrt Q}` (eq 18, the default;
  theorem 1 holds for any correlation valid in every dimension) or exp(-Q) (their squared
  exponential). With constant parameters it is eq 18 to rounding.
* :func:`sample_nonstationary`: white noise smoothed by a kernel that changes with position,
  approximated by K stationary kernels. K anchors (lambda_a, lambda_b, phi) are chosen by
  k-means in the log-Euclidean coordinates of S (every distinct set when there are <= K);
  ONE white-noise torus is filtered by each anchor's symmetric square root of its circulant
  embedding (:mod:`roughgp.sampling.circulant`: the same draw, the same noise for every
  anchor); the K fields are blended pointwise with linear weights between the two nearest
  anchors, the blend is divided by its exact local standard deviation and multiplied by
  s(x) = sqrt(variance(x)): the local variance is exact, the correlation approximate.
  Then the nugget ``noise_variance(x)`` (eq 8) is added per point.

Approximations: (1) lengths and angle take only K values, blended between neighbours; (2) the
cross-covariance of two anchors is that of their square-root filters, which for the squared
exponential is Paciorek's form (Higdon's process convolution) but for eq 18's exponential is
not, so the exponential blend keeps an error as K grows. :func:`blend_covariance` returns the
blend's exact covariance (it is linear in the white noise). Measured by
``benchmarks/nonstationary_sampler.py`` (32 x 32, dx = 1, lambda_a 2 -> 8, lambda_b 1.5 -> 3,
phi 0 -> 60 deg left to right), relative Frobenius error of the covariance for K = 1, 4, 8, 16:
0.31, 0.046, 0.017, 0.009 (eq 18), 0.39, 0.063, 0.020, 0.004 (squared exponential); the table
per lag and region is in that script's docstring.

Fitting local parameters to a measurement (local likelihood: Risser & Calder 2017, J. Stat.
Softw. 81(14), the R package convoSPAT) is not done here. Angles are in radians, as everywhere
in roughgp's hyperparameters; positions in the unit of the lengths (um); maps are z[iy, ix].
"""

from __future__ import annotations

from dataclasses import dataclass, field as _field

import numpy as np

from roughgp.common.checks import as_generator, check_finite, check_integer, check_nonnegative
from roughgp.common.checks import check_positive
from roughgp.common.grid import coordinates, normalize
from roughgp.sampling import circulant
from roughgp.sampling.truncation import tapered_eigenvalues

__all__ = ["CORRELATIONS", "ParameterField", "paciorek_covariance", "BlendPlan", "blend_plan",
           "blend_covariance", "sample_nonstationary"]

CORRELATIONS = ("exponential", "squared_exponential")
_NAMES = ("variance", "lambda_a", "lambda_b", "angle", "noise_variance")
_CHECKS = {"variance": check_positive, "lambda_a": check_positive, "lambda_b": check_positive,
           "angle": check_finite, "noise_variance": check_nonnegative}


@dataclass(frozen=True)
class ParameterField:
    """Local eq 18 parameters: each a number, an array of the points' shape (z[iy, ix] on a
    grid) or a callable ``f(x, y)`` of position arrays (um) returning an array of their shape.

    Attributes:
        variance: sigma_k^2 > 0 (um^2). lambda_a, lambda_b: lengths > 0 (um), along and
        across the lay. angle: phi in radians (finite). noise_variance: eq 8's >= 0 (um^2).
    """

    variance: object = 1.0
    lambda_a: object = 1.0
    lambda_b: object = 1.0
    angle: object = 0.0
    noise_variance: object = 0.0

    def __post_init__(self):
        for name in _NAMES:
            value = getattr(self, name)
            if not callable(value):
                _CHECKS[name](name, np.asarray(value, dtype=np.float64))

    def at(self, points) -> dict:
        """The parameters at ``points`` of shape (..., 2), (x, y) components: arrays of shape
        ``points.shape[:-1]``; a ValueError naming the parameter when one is out of range."""
        points = np.asarray(points, dtype=np.float64)
        if points.ndim < 1 or points.shape[-1] != 2:
            raise ValueError(f"points must have shape (..., 2), (x, y), got {points.shape}")
        out = {}
        for name in _NAMES:
            value = getattr(self, name)
            if callable(value):
                value = value(points[..., 0], points[..., 1])
            value = np.asarray(value, dtype=np.float64)
            try:
                value = np.broadcast_to(value, points.shape[:-1])
            except ValueError:
                raise ValueError(f"{name} must be a number, a callable f(x, y) or an array of "
                                 f"shape {points.shape[:-1]}, got shape {value.shape}") from None
            _CHECKS[name](name, value)
            out[name] = value
        return out


def _matrices(values):
    """S = T^T diag(a^2, b^2) T as its entries (sxx, sxy, syy)."""
    c, s = np.cos(values["angle"]), np.sin(values["angle"])
    a2, b2 = values["lambda_a"] ** 2, values["lambda_b"] ** 2
    return c * c * a2 + s * s * b2, c * s * (a2 - b2), s * s * a2 + c * c * b2


def _check_correlation(correlation):
    if correlation not in CORRELATIONS:
        raise ValueError(f"correlation must be one of {CORRELATIONS}, got {correlation!r}")


def _rho(q, correlation):
    _check_correlation(correlation)
    return np.exp(-np.sqrt(np.maximum(q, 0.0))) if correlation == "exponential" else np.exp(-q)


def paciorek_covariance(points_a, points_b, field: ParameterField, *,
                        correlation="exponential", noise=False) -> np.ndarray:
    """The Paciorek-Schervish covariance (module docstring) between ``points_a`` (..., 2) and
    ``points_b`` (..., 2), shape ``(*a.shape[:-1], *b.shape[:-1])``. ``noise=True`` adds
    ``noise_variance`` where two points coincide (eq 8's nugget)."""
    pa, pb = np.asarray(points_a, np.float64), np.asarray(points_b, np.float64)
    va, vb = field.at(pa), field.at(pb)
    shape = pa.shape[:-1] + pb.shape[:-1]
    pa, pb = pa.reshape(-1, 2), pb.reshape(-1, 2)
    (axx, axy, ayy), (bxx, bxy, byy) = (
        [m.reshape(-1) for m in _matrices(v)] for v in (va, vb))
    mxx, mxy, myy = ((u[:, None] + w[None, :]) / 2 for u, w in
                     ((axx, bxx), (axy, bxy), (ayy, byy)))
    det = mxx * myy - mxy * mxy
    dx, dy = pa[:, None, 0] - pb[None, :, 0], pa[:, None, 1] - pb[None, :, 1]
    q = (myy * dx * dx - 2 * mxy * dx * dy + mxx * dy * dy) / det
    sa, sb = (np.sqrt(v["variance"] * v["lambda_a"] * v["lambda_b"]).reshape(-1)
              for v in (va, vb))  # s(x) |S(x)|^1/4
    cov = sa[:, None] * sb[None, :] / np.sqrt(det) * _rho(q, correlation)
    if noise:
        same = (dx == 0) & (dy == 0)
        cov += same * np.sqrt(va["noise_variance"].reshape(-1)[:, None]
                              * vb["noise_variance"].reshape(-1)[None, :])
    return cov.reshape(shape)


def _log_features(values):
    """log S as a point of R^3 (xx, yy, sqrt2 xy): the log-Euclidean metric of SPD matrices."""
    c, s = np.cos(values["angle"]), np.sin(values["angle"])
    la, lb = 2 * np.log(values["lambda_a"]), 2 * np.log(values["lambda_b"])
    return np.stack([c * c * la + s * s * lb, s * s * la + c * c * lb,
                     np.sqrt(2) * c * s * (la - lb)], axis=-1).reshape(-1, 3)


def _anchors(features, k):
    """K anchor features: the distinct ones when there are <= K, else k-means (farthest-point
    start from the point nearest the mean, then Lloyd steps), on at most 4096 points."""
    distinct = np.unique(features.round(12), axis=0)
    if len(distinct) <= k:
        return distinct
    sub = features[:: max(1, len(features) // 4096)]
    centres = [sub[np.argmin(((sub - sub.mean(0)) ** 2).sum(1))]]
    for _ in range(k - 1):
        d = np.min([((sub - c) ** 2).sum(1) for c in centres], axis=0)
        centres.append(sub[np.argmax(d)])
    centres = np.array(centres)
    for _ in range(50):
        label = np.argmin(((sub[:, None] - centres[None]) ** 2).sum(-1), axis=1)
        new = np.array([sub[label == j].mean(0) if np.any(label == j) else centres[j]
                        for j in range(k)])
        if np.allclose(new, centres, rtol=0, atol=1e-12):
            break
        centres = new
    return centres


def _weights(features, anchors):
    """(K, N) weights: 1 - t and t on the nearest anchor i and the second nearest j, t the
    projection of the point on the segment i -> j clipped to [0, 1]."""
    weights = np.zeros((len(anchors), len(features)))
    if len(anchors) == 1:
        weights[0] = 1.0
        return weights
    d = ((features[:, None] - anchors[None]) ** 2).sum(-1)
    order = np.argsort(d, axis=1, kind="stable")
    i, j = order[:, 0], order[:, 1]
    seg = anchors[j] - anchors[i]
    length2 = np.maximum((seg * seg).sum(1), np.finfo(float).tiny)
    t = np.clip(((features - anchors[i]) * seg).sum(1) / length2, 0.0, 1.0)
    cols = np.arange(len(features))
    weights[i, cols] += 1 - t
    weights[j, cols] += t
    return weights


def _anchor_acvf(feature, correlation):
    """The unit-variance stationary ACVF of an anchor (eq 18's form with S = exp(log S))."""
    lxx, lyy, lxy = feature[0], feature[1], feature[2] / np.sqrt(2)
    vals, vecs = np.linalg.eigh(np.array([[lxx, lxy], [lxy, lyy]]))
    inverse = vecs @ np.diag(np.exp(-vals)) @ vecs.T  # S^-1

    def acvf(lags):
        lags = np.asarray(lags, dtype=np.float64)
        return _rho(np.einsum("...i,ij,...j->...", lags, inverse, lags), correlation)
    return acvf


@dataclass(frozen=True)
class BlendPlan:
    """What a blended draw needs. ``anchors`` (K, 3): log S of each anchor; ``weights`` and
    ``amplitude`` (K, ny, nx): w_k(x) and s(x) w_k(x) / n(x), n(x)^2 = w^T G w;
    ``embeddings``: one circulant square root per anchor on a common torus; ``gram`` (K, K):
    the anchors' covariances at lag 0, G; ``noise_sd`` (ny, nx); ``clipped_fraction``: the
    largest share of an anchor's trace lost to negative eigenvalues set to 0."""

    anchors: np.ndarray
    weights: np.ndarray
    amplitude: np.ndarray
    embeddings: tuple = _field(repr=False)
    gram: np.ndarray = _field(repr=False)
    noise_sd: np.ndarray = _field(repr=False)
    clipped_fraction: float = 0.0


def blend_plan(shape, spacing, field: ParameterField, *, n_kernels=4,
               correlation="exponential") -> BlendPlan:
    """Anchors, weights and square-root filters of :func:`sample_nonstationary`."""
    shape, spacing = normalize(shape, spacing)
    if len(shape) != 2:
        raise ValueError(f"shape must be (ny, nx) for a surface, got {shape!r}")
    k = check_integer("n_kernels", n_kernels, 1, 64)
    _check_correlation(correlation)
    values = field.at(coordinates(shape, spacing))
    features = _log_features(values)
    anchors = _anchors(features, k)
    weights = _weights(features, anchors)
    acvfs = [_anchor_acvf(a, correlation) for a in anchors]
    tori = [circulant.embed(f, shape, spacing, approximate=True).torus_shape for f in acvfs]
    torus = tuple(int(m) for m in np.max(tori, axis=0))
    scales, clipped = [], 0.0
    for f in acvfs:
        eig = tapered_eigenvalues(f, torus, tuple(spacing), shape)[0]
        clipped = max(clipped, float(-eig[eig < 0].sum() / eig.sum()))
        scales.append(np.sqrt(np.clip(eig, 0.0, None) / eig.size))
    embeddings = tuple(circulant.Embedding(shape, tuple(spacing), torus, s, 0.0, clipped, (),
                                           "smooth") for s in scales)
    gram = np.array([[np.sum(sj * sk) for sk in scales] for sj in scales])
    norm = np.sqrt(np.einsum("jn,jk,kn->n", weights, gram, weights))
    amplitude = weights * np.sqrt(values["variance"]).reshape(-1) / norm
    return BlendPlan(anchors, weights.reshape(-1, *shape), amplitude.reshape(-1, *shape),
                     embeddings, gram, np.sqrt(values["noise_variance"]), clipped)


def blend_covariance(plan: BlendPlan, *, noise=False) -> np.ndarray:
    """The exact (N, N) covariance of the blended draw (N = ny nx, row-major points): the
    draw is linear in the white noise, sum_jk a_j(x) a_k(x') c_jk(x - x'). Small grids."""
    ny, nx = plan.amplitude.shape[1:]
    my, mx = plan.embeddings[0].torus_shape
    iy, ix = np.divmod(np.arange(ny * nx), nx)
    lag = ((iy[:, None] - iy[None, :]) % my) * mx + (ix[:, None] - ix[None, :]) % mx
    a = plan.amplitude.reshape(len(plan.anchors), -1)
    scales = [e.scale for e in plan.embeddings]
    cov = np.zeros((ny * nx, ny * nx))
    for j in range(len(a)):
        for k in range(len(a)):
            if np.any(a[j]) and np.any(a[k]):  # c_jk = FFT(s_j s_k), the cross-covariance
                cross = np.fft.fft2(scales[j] * scales[k]).real.reshape(-1)
                cov += a[j][:, None] * a[k][None, :] * cross[lag]
    if noise:
        cov[np.diag_indices_from(cov)] += plan.noise_sd.reshape(-1) ** 2
    return cov


def sample_nonstationary(shape, spacing, field: ParameterField, *, n_kernels=4,
                         correlation="exponential", n_samples=1, seed=None, latent=False,
                         plan: BlendPlan | None = None) -> np.ndarray:
    """Draws of the non-stationary eq 18 surface by the K-kernel blend (module docstring).

    Args:
        shape: ``(ny, nx)``; spacing: ``(dy, dx)`` or a scalar, in um.
        field: the local parameters (:class:`ParameterField`).
        n_kernels: K >= 1, the number of stationary kernels blended.
        correlation: ``"exponential"`` (eq 18) or ``"squared_exponential"``.
        n_samples: the number of draws; seed: int, None or a Generator (same seed, same draws).
        latent: drop the nugget. plan: a :func:`blend_plan` for these arguments, to reuse.

    Returns:
        Shape ``(n_samples, ny, nx)``, z[iy, ix] per draw.
    """
    n = check_integer("n_samples", n_samples, 1)
    rng = as_generator(seed)
    plan = plan or blend_plan(shape, spacing, field, n_kernels=n_kernels,
                              correlation=correlation)
    noise_seed = int(rng.integers(2**63))
    out = np.zeros((n, *plan.amplitude.shape[1:]))
    for amplitude, embedding in zip(plan.amplitude, plan.embeddings):
        if np.any(amplitude):  # the same white noise for every anchor: one seed, one stream
            out += amplitude * circulant.draw(embedding, n, np.random.default_rng(noise_seed))
    if not latent:
        out += plan.noise_sd * rng.standard_normal(out.shape)
    return out
