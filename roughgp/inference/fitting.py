r"""Marginal-likelihood fit of the spectral mixture ACVF (eq 21) to a profile: section 3.3.

The paper's procedure for turned profiles (after Wilson & Adams 2013):

1. estimate the PSD of the profile by Welch's method and by the periodogram
   (:mod:`roughgp.metrology.spectral`);
2. fit a Q-component Gaussian mixture to each noisy estimate by inverse-transform sampling
   (draw frequencies from the normalised one-sided PSD, fit the mixture by EM), several times
   with different sub-seeds: each fitted (weight, mean, variance) set is one *candidate*
   initialisation;
3. score every candidate by its exact log marginal likelihood, optimise the best few over all
   hyperparameters and keep the best final likelihood.

The fitting problem is multi-modal, so :class:`SpectralMixtureFit` keeps every candidate with
its starting and (when optimised) final log marginal likelihood.

The exact likelihood and its gradient come from :mod:`roughgp.gp.toeplitz` (Levinson-Durbin
plus Gohberg-Semencul, :math:`O(n^2)` per evaluation); the chain rule to the hyperparameters
of eq 21 is :math:`O(Qn)`.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
from scipy import optimize

from roughgp.common.checks import as_generator, check_finite, check_integer, check_scale
from roughgp.common.device import resolve as resolve_device
from roughgp.common.numerics import perturbed_start
from roughgp.gp.toeplitz import (
    dense_log_likelihood_terms,
    toeplitz_log_likelihood,
    toeplitz_log_likelihood_terms,
)
from roughgp.metrology import spectral

__all__ = ["toeplitz_log_likelihood", "spectral_mixture_log_likelihood",
           "fit_spectral_mixture", "SpectralMixtureFit", "Candidate", "MIN_POINTS",
           "MIN_LINE_WIDTH", "check_profile", "MAX_POINTS", "MAX_MIXTURES", "MAX_CANDIDATES"]

MIN_POINTS = 16
"""Fewest profile points :func:`fit_spectral_mixture` accepts."""

MAX_POINTS = 65536
"""Most profile points :func:`fit_spectral_mixture` accepts: the exact likelihood of eq 21
costs O(n^2) per optimiser step (the Levinson recursion; a dense factorisation on a device),
so 65536 points already take hours on the CPU; 10^6 would take weeks. Crop or decimate."""

MAX_MIXTURES = 100
"""Most spectral-mixture components Q (eq 21): each optimiser step costs O(Q n^2), and
beyond a few tens of lines the fit resolves nothing a profile can tell apart."""

MAX_CANDIDATES = 1000
"""Most initialisations scored (each a short optimisation of the exact likelihood)."""

MIN_LINE_WIDTH = 0.05
"""Narrowest spectral line of a fit, as a standard deviation in cycles per profile length:
a narrower line is indistinguishable from a pure one on the profile (its ACVF envelope still
holds 95 % after one profile length), and a floor keeps the fitted ACVF decaying, so the
model can be simulated on a finite circulant torus (about 30 profile lengths)."""

_TWO_PI = 2.0 * math.pi


# ------------------------------------------------------ spectral mixture on a grid

def _sm_acvf_terms(h, weights, means, variances):
    """Per-component cos and envelope at integer lags ``h`` (cycles per sample units)."""
    phase = _TWO_PI * np.outer(means, h)
    envelope = np.exp(-2.0 * math.pi ** 2 * np.outer(variances, h * h))
    return np.cos(phase), np.sin(phase), envelope


def _sm_loglik_grad(z, weights, means, variances, noise, gradient=True, device=None):
    """Log-likelihood of ``z`` (sample units) and its gradient with respect to
    (weights, means, variances, noise); on ``device`` by the dense route of
    :mod:`roughgp.gp.toeplitz`."""
    h = np.arange(z.size, dtype=np.float64)
    cos, sin, env = _sm_acvf_terms(h, weights, means, variances)
    ce = cos * env
    r = weights @ ce
    r[0] += noise
    if device is None:
        loglik, g = toeplitz_log_likelihood_terms(z, r, gradient)
    else:
        loglik, g = dense_log_likelihood_terms(z, r, gradient, device)
    if not gradient:
        return loglik, None
    d_w = ce @ g
    d_mu = -_TWO_PI * weights * ((sin * env) @ (h * g))
    d_var = -2.0 * math.pi ** 2 * weights * (ce @ (h * h * g))
    return loglik, (d_w, d_mu, d_var, g[0])


def check_profile(x, z):
    """``(x, z)`` as float64 1-D arrays of one length on a regular, increasing grid; a
    ValueError naming the problem otherwise."""
    x = np.asarray(x, dtype=np.float64)
    z = np.asarray(z, dtype=np.float64)
    if x.ndim != 1 or z.ndim != 1 or x.shape != z.shape:
        raise ValueError(f"x and z must be 1-D of the same length, got shapes {x.shape} and "
                         f"{z.shape}")
    if z.size < MIN_POINTS:
        raise ValueError(f"z must have at least {MIN_POINTS} points (allowed range: "
                         f"[{MIN_POINTS}, inf)), got {z.size}")
    check_finite("x", x)
    check_finite("z", z)
    dx = np.diff(x)
    spacing = (x[-1] - x[0]) / (x.size - 1)
    if not spacing > 0 or np.max(np.abs(dx - spacing)) > 1e-6 * spacing:
        raise ValueError("x must be a regular, increasing grid (equal spacing > 0 to a "
                         f"relative 1e-6), got spacings in [{dx.min():.6g}, {dx.max():.6g}]")
    check_scale("the spacing of x", spacing)  # 1e-300 gave infinite variances
    return x, z, spacing


def _check_mixture_parameters(weights, means, variances, noise_variance):
    weights = np.atleast_1d(np.asarray(weights, dtype=np.float64))
    q = weights.size
    means = np.asarray(means, dtype=np.float64).reshape(-1)
    variances = np.asarray(variances, dtype=np.float64).reshape(-1)
    if weights.ndim != 1 or means.size != q or variances.size != q:
        raise ValueError(f"weights, means and variances must each hold Q values (one per "
                         f"component), got sizes {weights.size}, {means.size}, "
                         f"{variances.size}")
    for name, value in (("weights", weights), ("variances", variances)):
        check_finite(name, value)
        if np.any(value <= 0):
            raise ValueError(f"{name} must be > 0 (allowed range: (0, inf)), got "
                             f"{value.tolist()!r}")
    check_finite("means", means)
    if not (np.isfinite(noise_variance) and noise_variance >= 0):
        raise ValueError(f"noise_variance must be >= 0 (allowed range: [0, inf)), got "
                         f"{noise_variance!r}")
    return weights, means, variances, float(noise_variance)


def spectral_mixture_log_likelihood(x, z, weights, means, variances, noise_variance, *,
                                    gradient=False):
    r"""Exact log marginal likelihood of a zero-mean profile under eq 21 plus white noise.

    Args:
        x: positions, a regular grid (shape (n,)).
        z: heights (shape (n,)), used as given (no mean is removed here).
        weights, means, variances: shape (Q,) each; ``means`` in cycles per unit of x,
            ``variances`` in cycles^2 per unit^2.
        noise_variance: >= 0, added on the diagonal.
        gradient: also return the gradient, a dict with keys ``"weights"``, ``"means"``,
            ``"variances"`` (shape (Q,) each) and ``"noise_variance"`` (float), with respect
            to the parameters in the units given.

    Returns:
        the log marginal likelihood, or ``(loglik, grad)``.
    """
    x, z, spacing = check_profile(x, z)
    weights, means, variances, noise = _check_mixture_parameters(weights, means, variances,
                                                                 noise_variance)
    try:
        loglik, grads = _sm_loglik_grad(z, weights, means * spacing, variances * spacing ** 2,
                                        noise, gradient)
    except np.linalg.LinAlgError:
        raise ValueError("the covariance of these hyperparameters is not positive definite "
                         "on this grid (try noise_variance > 0)") from None
    if not gradient:
        return loglik
    d_w, d_mu, d_var, d_noise = grads
    return loglik, {"weights": d_w, "means": d_mu * spacing, "variances": d_var * spacing ** 2,
                    "noise_variance": float(d_noise)}


# ------------------------------------------------------ initialisation (section 3.3)

def _kmeanspp(samples, q, rng):
    centres = [samples[rng.integers(samples.size)]]
    for _ in range(1, q):
        d2 = np.min((samples[:, None] - np.asarray(centres)[None, :]) ** 2, axis=1)
        total = d2.sum()
        p = d2 / total if total > 0 else None
        centres.append(samples[rng.choice(samples.size, p=p)])
    return np.asarray(centres)


def _gmm_em(samples, q, rng, var_floor, max_iter=300, tol=1e-9):
    """Seeded EM for a 1-D Gaussian mixture: (proportions, means, variances)."""
    means = _kmeanspp(samples, q, rng)
    variances = np.full(q, max(samples.var(), var_floor))
    props = np.full(q, 1.0 / q)
    previous = -np.inf
    for _ in range(max_iter):
        log_p = (np.log(props) - 0.5 * np.log(_TWO_PI * variances)
                 - 0.5 * (samples[:, None] - means) ** 2 / variances)
        top = log_p.max(axis=1, keepdims=True)
        log_norm = top[:, 0] + np.log(np.exp(log_p - top).sum(axis=1))
        resp = np.exp(log_p - log_norm[:, None])
        mass = resp.sum(axis=0) + 1e-12
        props = mass / mass.sum()
        means = (resp * samples[:, None]).sum(axis=0) / mass
        variances = np.maximum((resp * (samples[:, None] - means) ** 2).sum(axis=0) / mass,
                               var_floor)
        current = log_norm.mean()
        if abs(current - previous) < tol:
            break
        previous = current
    props = np.maximum(props, 1e-6)
    return props / props.sum(), means, variances


def _one_sided(freqs, power):
    freqs = np.asarray(freqs).reshape(-1)
    keep = freqs > 0
    return freqs[keep], np.asarray(power)[keep]


def _initialisations(z, q, n_candidates, n_draws, welch_segment, noise_fraction, rng):
    """Candidates in sample units: list of (source, subseed, weights, means, variances)."""
    n = z.size
    pf, pp = spectral.periodogram(z, 1.0)
    wf, wp = spectral.welch(z, 1.0, segment_length=welch_segment)
    sources = [("welch", *_one_sided(wf, wp), 1.0 / welch_segment),
               ("periodogram", *_one_sided(pf, pp), 1.0 / n)]
    n_welch = n_candidates // 2
    counts = (n_welch, n_candidates - n_welch)
    total = z.var() * (1.0 - noise_fraction)
    out = []
    for (name, freqs, power, df), count in zip(sources, counts):
        p = np.clip(power, 0.0, None)
        p = p / p.sum()
        for _ in range(count):
            subseed = int(rng.integers(2 ** 63 - 1))
            sub = np.random.default_rng(subseed)
            idx = sub.choice(freqs.size, size=n_draws, p=p)
            samples = np.abs(freqs[idx] + sub.uniform(-0.5, 0.5, n_draws) * df)
            props, means, variances = _gmm_em(samples, q, sub, var_floor=df * df / 12.0)
            out.append((name, subseed, total * props, np.abs(means), variances))
    return out


# ------------------------------------------------------------------ results

@dataclasses.dataclass(frozen=True)
class Candidate:
    """One initialisation of :func:`fit_spectral_mixture` (units of x, like the fit).

    ``source``: ``"welch"`` or ``"periodogram"`` (the PSD estimate it was fitted to);
    ``subseed``: the seed of its inverse-transform draws and EM; ``weights``, ``means``,
    ``variances``, ``noise_variance``: its starting hyperparameters;
    ``initial_log_likelihood``: their exact log marginal likelihood;
    ``final_log_likelihood``: after optimisation (NaN if it was not optimised; after the
    screen only, if it lost the screen: see :func:`fit_spectral_mixture`);
    ``final``: the optimised (weights, means, variances, noise_variance), or None;
    ``optimised``, ``chosen``: whether it was optimised and whether the fit is its optimum.
    """

    source: str
    subseed: int
    weights: np.ndarray
    means: np.ndarray
    variances: np.ndarray
    noise_variance: float
    initial_log_likelihood: float
    final_log_likelihood: float = float("nan")
    final: tuple | None = None
    optimised: bool = False
    chosen: bool = False
    n_evaluations: int = 0
    message: str = ""


@dataclasses.dataclass(frozen=True)
class SpectralMixtureFit:
    """Result of :func:`fit_spectral_mixture` (frequencies in cycles per unit of x).

    ``weights``, ``means`` (>= 0), ``variances``: shape (Q,), sorted by decreasing weight;
    ``noise_variance``; ``mean``: the constant removed from z; ``log_marginal_likelihood``:
    exact, of the mean-removed profile; ``candidates``: every initialisation
    (:class:`Candidate`); ``chosen``: the index of the winning candidate; ``spacing``;
    ``n_points``: the length of the profile.
    """

    weights: np.ndarray
    means: np.ndarray
    variances: np.ndarray
    noise_variance: float
    log_marginal_likelihood: float
    mean: float
    spacing: float
    candidates: list
    chosen: int
    n_points: int

    @property
    def dominant_component(self) -> int:
        """Index of the component with the highest spectral peak, ``weight / sqrt(variance)``
        (the PSD of eq 21 at its mean), among those whose period ``1 / mean`` fits in the
        profile: the sharpest strong line of the spectrum, a turned profile's feed."""
        length = self.n_points * self.spacing
        peak = self.weights / np.sqrt(self.variances)
        peak = np.where(self.means * length >= 1.0, peak, -np.inf)
        if not np.any(np.isfinite(peak)):
            raise ValueError("no fitted component has a period shorter than the profile")
        return int(np.argmax(peak))

    @property
    def dominant_period(self) -> float:
        """``1 / means[dominant_component]``, in units of x."""
        return float(1.0 / self.means[self.dominant_component])

    def acvf(self, lags):
        """The fitted eq 21 ACVF (without the noise) at scalar ``lags`` (any shape), in units
        of x."""
        t = np.asarray(lags, dtype=np.float64)
        out = np.zeros(t.shape)
        for w, mu, v in zip(self.weights, self.means, self.variances):
            out = out + w * np.cos(_TWO_PI * t * mu) * np.exp(-2 * math.pi ** 2 * t * t * v)
        return out

    def kernel(self):
        """A :class:`roughgp.gp.kernels.SpectralMixtureKernel` with the fitted parameters."""
        from roughgp.gp.kernels import SpectralMixtureKernel
        q = self.weights.size
        return SpectralMixtureKernel(q, dim=1, weights=self.weights,
                                     means=self.means.reshape(q, 1),
                                     variances=self.variances.reshape(q, 1))


# ------------------------------------------------------------------ the fit

def fit_spectral_mixture(x, z, num_mixtures, *, n_candidates=10, n_optimise=3, seed=None,
                         noise_fraction=0.1, n_draws=2000, welch_segment=None, maxiter=200,
                         screen_iter=30, min_noise_fraction=1e-6, device=None):
    r"""Fit eq 21 plus white noise to a profile by the procedure of section 3.3.

    The sample mean of ``z`` is removed first (a constant, unknown mean estimated by the
    sample mean; it is returned as ``mean``); the likelihood is that of the centred profile
    under a zero-mean GP. Internally the profile is scaled to unit variance and lags are
    counted in samples; results are returned in the units of x and z.

    Steps: (1) Welch (segments of ``welch_segment`` points) and periodogram estimates of the
    PSD; (2) ``n_candidates`` initialisations, half from each estimate (the periodogram gets
    the odd one): ``n_draws`` frequencies drawn from the normalised one-sided PSD (jittered
    uniformly within a frequency bin), a Q-component Gaussian mixture fitted by seeded EM
    (k-means++ start), weights scaled so they sum to ``(1 - noise_fraction)`` times the
    variance of z and the noise variance set to ``noise_fraction`` times it; (3) the exact log
    marginal likelihood of every candidate; the ``n_optimise`` best are optimised with
    L-BFGS-B over log weights, log means, log variances and log noise variance with the exact
    likelihood and its exact gradient (module docstring), in two stages to bound the cost:
    each of them runs ``screen_iter`` iterations, then the one with the best likelihood after
    that screen continues (a fresh L-BFGS-B run from where it stopped) up to ``maxiter``
    iterations in all. With ``n_optimise=1`` the best start runs ``maxiter`` iterations. The
    screened-out candidates report the likelihood they reached in the screen.

    Bounds of the search (in sample units, the profile scaled to unit variance): weights in
    [1e-10, 1e3], means in [1e-3 / n, 0.5] (zero up to a period of 1000 profile lengths, up to
    the Nyquist frequency), variances in [(:data:`MIN_LINE_WIDTH` / n)^2, 1], noise variance in
    [``min_noise_fraction``, 10] (a floor that keeps K well conditioned).

    Args:
        x: positions, shape (n,), a regular increasing grid (checked to a relative 1e-6).
        z: heights, shape (n,), finite, n >= :data:`MIN_POINTS`.
        num_mixtures: Q >= 1.
        n_candidates: >= 1 initialisations. n_optimise: how many of the best to optimise
            (1..n_candidates). seed: int, None or Generator; the same seed gives the same
            candidates and fit.
        noise_fraction: in [0, 1): the starting noise share of the variance.
        n_draws: >= 10 inverse-transform draws per candidate.
        welch_segment: Welch segment length in [16, n]; default the power of two nearest
            n / 8, at least 64 (and at most n).
        maxiter: L-BFGS-B iterations of the winning candidate in all (>= 1).
        screen_iter: L-BFGS-B iterations of each of the ``n_optimise`` candidates in the
            screen (>= 1).
        min_noise_fraction: in (0, 1): the floor of the noise variance (a share of the
            variance of z).
        device: None (the Toeplitz recursion on the CPU) or a torch device such as
            ``"cuda"``: every likelihood and gradient then comes from the dense route of
            :mod:`roughgp.gp.toeplitz` on that device (the same numbers; the search itself,
            L-BFGS-B, stays on the CPU).

    Returns:
        :class:`SpectralMixtureFit`.
    """
    q = check_integer("num_mixtures", num_mixtures, 1, MAX_MIXTURES)
    n_candidates = check_integer("n_candidates", n_candidates, 1, MAX_CANDIDATES)
    n_optimise = check_integer("n_optimise", n_optimise, 1)
    if np.size(z) > MAX_POINTS:
        raise ValueError(f"z has {np.size(z)} points; the exact likelihood of eq 21 costs "
                         f"O(n^2) per step (allowed range: [{MIN_POINTS}, {MAX_POINTS}] "
                         f"points): crop or decimate the profile")
    x, z, spacing = check_profile(x, z)
    if n_optimise > n_candidates:
        raise ValueError(f"n_optimise must be in [1, n_candidates = {n_candidates}], "
                         f"got {n_optimise}")
    n_draws = check_integer("n_draws", n_draws, 10)
    maxiter = check_integer("maxiter", maxiter, 1)
    screen_iter = check_integer("screen_iter", screen_iter, 1)
    if not (isinstance(noise_fraction, (int, float, np.floating)) and 0 <= noise_fraction < 1):
        raise ValueError(f"noise_fraction must be in [0, 1), got {noise_fraction!r}")
    if not (isinstance(min_noise_fraction, (int, float, np.floating))
            and 0 < min_noise_fraction < 1):
        raise ValueError(f"min_noise_fraction must be in (0, 1), got {min_noise_fraction!r}")
    n = z.size
    if welch_segment is None:
        welch_segment = min(n, max(64, 2 ** int(round(math.log2(n / 8)))))
    welch_segment = check_integer("welch_segment", welch_segment, 16)
    if welch_segment > n:
        raise ValueError(f"welch_segment must be in [16, n = {n}], got {welch_segment}")
    rng = as_generator(seed)
    device = resolve_device(device)

    mean = float(z.mean())
    scale = float(z.std())
    if not scale > 0:
        raise ValueError("z must not be constant (its variance is 0)")
    zs = (z - mean) / scale
    noise0 = max(noise_fraction, min_noise_fraction)

    lower = np.concatenate((np.full(q, math.log(1e-10)), np.full(q, math.log(1e-3 / n)),
                            np.full(q, math.log((MIN_LINE_WIDTH / n) ** 2)),
                            [math.log(min_noise_fraction)]))
    upper = np.concatenate((np.full(q, math.log(1e3)), np.full(q, math.log(0.5)),
                            np.full(q, 0.0), [math.log(10.0)]))

    def unpack(theta):
        e = np.exp(theta)
        return e[:q], e[q:2 * q], e[2 * q:3 * q], e[3 * q]

    def objective(theta):
        w, mu, var, noise = unpack(theta)
        try:
            loglik, (d_w, d_mu, d_var, d_noise) = _sm_loglik_grad(zs, w, mu, var, noise,
                                                                  device=device)
        except np.linalg.LinAlgError:
            return 1e10, np.zeros_like(theta)
        grad = np.concatenate((d_w * w, d_mu * mu, d_var * var, [d_noise * noise]))
        return -loglik / n, -grad / n

    def log_ml(theta):
        w, mu, var, noise = unpack(theta)
        try:
            return _sm_loglik_grad(zs, w, mu, var, noise, gradient=False, device=device)[0]
        except np.linalg.LinAlgError:
            return -np.inf

    log_jacobian = -n * math.log(scale)  # density of z from that of the scaled profile
    starts = []
    for source, subseed, w, mu, var in _initialisations(zs, q, n_candidates, n_draws,
                                                         welch_segment, noise0, rng):
        theta = perturbed_start(np.clip(np.log(np.concatenate((w, mu, var, [noise0]))),
                                        lower, upper), lower, upper)
        starts.append((source, subseed, theta, log_ml(theta)))

    order = sorted(range(len(starts)), key=lambda k: -starts[k][3]
                   if np.isfinite(starts[k][3]) else np.inf)
    bounds = list(zip(lower, upper))

    def run(theta, iterations):
        res = optimize.minimize(objective, theta, jac=True, method="L-BFGS-B", bounds=bounds,
                                options={"maxiter": iterations})
        return res.x, log_ml(res.x), int(res.nfev), int(res.nit), str(res.message)

    finals = {}  # stage 1: screen the n_optimise best starts with a short run each
    for k in order[:n_optimise]:
        finals[k] = run(starts[k][2], min(screen_iter, maxiter) if n_optimise > 1 else maxiter)
    best = max(finals, key=lambda k: finals[k][1])
    theta, ll, nfev, nit, message = finals[best]
    if nit < maxiter and n_optimise > 1 and not message.startswith("CONVERGENCE"):
        theta, ll, nfev2, nit2, message = run(theta, maxiter - nit)  # stage 2: the winner
        finals[best] = (theta, ll, nfev + nfev2, nit + nit2, message)

    def to_units(theta):
        w, mu, var, noise = unpack(theta)
        return (w * scale ** 2, mu / spacing, var / spacing ** 2, float(noise * scale ** 2))

    candidates = []
    for k, (source, subseed, theta, ll0) in enumerate(starts):
        w, mu, var, noise = to_units(theta)
        extra = {}
        if k in finals:
            theta_f, ll_f, nfev, _, message = finals[k]
            extra = dict(final_log_likelihood=ll_f + log_jacobian, final=to_units(theta_f),
                         optimised=True, chosen=k == best, n_evaluations=nfev,
                         message=message)
        candidates.append(Candidate(source, subseed, w, mu, var, noise, ll0 + log_jacobian,
                                    **extra))
    w, mu, var, noise = to_units(finals[best][0])
    by_weight = np.argsort(-w, kind="stable")
    return SpectralMixtureFit(weights=w[by_weight], means=mu[by_weight],
                              variances=var[by_weight], noise_variance=noise,
                              log_marginal_likelihood=finals[best][1] + log_jacobian,
                              mean=mean, spacing=spacing, candidates=candidates, chosen=best,
                              n_points=n)
