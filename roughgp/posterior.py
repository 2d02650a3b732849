r"""Posterior sampling of GP hyperparameters (with the noise variance) by MCMC.

Section 2.2 of the paper: with surface data, the hyperparameters
:math:`\boldsymbol\alpha` "are usually optimized by maximizing the marginal likelihood
... or by sampling with the marginal likelihood". :mod:`roughgp.fitting` does the first;
this module does the second, with the affine-invariant ensemble sampler of emcee.

A model is a list of :class:`Parameter` (a name and a prior) and a log-likelihood, a
function of a dict ``name -> value`` of hyperparameters in their natural units.
The sampler works in an unconstrained parameter ``u``: ``u = log(theta)`` for positive
scales (:class:`LogUniform`, :class:`LogNormal`), ``u = theta`` for a bounded
:class:`Uniform` or for an angle (:class:`UniformAngle`). Every prior's ``logpdf`` is the
density *in u* (the Jacobian of the transform included), so

.. math::
    \log p(u \mid z) = \log p(z \mid \theta(u)) + \sum_j \log p_j(u_j) + \text{const}.

Two likelihoods are ready-made: :func:`profile_likelihood` (a 1-D profile on a regular grid,
exact in :math:`O(n^2)` by :func:`roughgp.toeplitz.toeplitz_log_likelihood`) and
:func:`grid_likelihood` (a small 2-D patch, dense Cholesky), with the models
:func:`spectral_mixture_profile_model` (eq 21 plus noise) and :func:`ground_patch_model`
(eq 18 plus noise). :func:`sample_posterior` runs the chain and refuses to report a
posterior from a chain shorter than ``min_tau_multiple`` (50) autocorrelation times unless
asked (:class:`ShortChainError`).
"""

from __future__ import annotations

import dataclasses
import math
from typing import Callable, Mapping

import numpy as np
import scipy.linalg

from roughgp._checks import as_generator, check_finite, check_integer, check_positive
from roughgp.device import check_memory, gaussian_log_density
from roughgp.device import resolve as resolve_device
from roughgp.grid import normalize
from roughgp.sampling import grid_covariance
from roughgp.toeplitz import toeplitz_log_likelihood

__all__ = [
    "LogUniform", "LogNormal", "Uniform", "UniformAngle", "Parameter", "PosteriorModel",
    "PosteriorSamples", "ShortChainError", "profile_likelihood", "grid_likelihood",
    "spectral_mixture_profile_model", "ground_patch_model", "sample_posterior",
    "maximum_a_posteriori", "order_lengthscales", "main_mode", "MAX_GRID_POINTS",
]

MAX_GRID_POINTS = 4096
"""Largest patch :func:`grid_likelihood` accepts: one evaluation factorises an (N, N) matrix
(4096 points: 128 MiB and about a second; a chain needs 10^4-10^5 evaluations)."""

_LOG_2PI = math.log(2.0 * math.pi)


# ------------------------------------------------------------------ priors

@dataclasses.dataclass(frozen=True)
class LogUniform:
    """``p(theta) ∝ 1/theta`` on ``[low, high]`` (scale-invariant), ``u = log theta``:
    uniform in u on ``[log low, log high]``."""

    low: float
    high: float

    def __post_init__(self):
        check_positive("low", self.low)
        check_positive("high", self.high)
        if not self.high > self.low:
            raise ValueError(f"high must be > low, got low={self.low!r}, high={self.high!r}")

    def logpdf(self, u):
        a, b = math.log(self.low), math.log(self.high)
        u = np.asarray(u, dtype=np.float64)
        return np.where((u >= a) & (u <= b), -math.log(b - a), -np.inf)

    def to_natural(self, u):
        return np.exp(u)

    def to_unconstrained(self, theta):
        return np.log(theta)

    def sample(self, rng, size=None):
        return as_generator(rng).uniform(math.log(self.low), math.log(self.high), size)


@dataclasses.dataclass(frozen=True)
class LogNormal:
    """``log theta ~ N(mu, sigma^2)`` (median ``exp(mu)``), ``u = log theta``: normal in u."""

    mu: float
    sigma: float

    def __post_init__(self):
        check_finite("mu", self.mu)
        check_positive("sigma", self.sigma)

    def logpdf(self, u):
        t = (np.asarray(u, dtype=np.float64) - self.mu) / self.sigma
        return -0.5 * t * t - math.log(self.sigma) - 0.5 * _LOG_2PI

    def to_natural(self, u):
        return np.exp(u)

    def to_unconstrained(self, theta):
        return np.log(theta)

    def sample(self, rng, size=None):
        return as_generator(rng).normal(self.mu, self.sigma, size)


@dataclasses.dataclass(frozen=True)
class Uniform:
    """Flat on ``[low, high]`` in the natural parameter (a location, e.g. a spectral-mixture
    mean frequency, which may be 0); ``u = theta``."""

    low: float
    high: float

    def __post_init__(self):
        check_finite("low", self.low)
        check_finite("high", self.high)
        if not self.high > self.low:
            raise ValueError(f"high must be > low, got low={self.low!r}, high={self.high!r}")

    def logpdf(self, u):
        u = np.asarray(u, dtype=np.float64)
        return np.where((u >= self.low) & (u <= self.high), -math.log(self.high - self.low),
                        -np.inf)

    def to_natural(self, u):
        return np.asarray(u, dtype=np.float64)

    def to_unconstrained(self, theta):
        return np.asarray(theta, dtype=np.float64)

    def sample(self, rng, size=None):
        return as_generator(rng).uniform(self.low, self.high, size)


@dataclasses.dataclass(frozen=True)
class UniformAngle:
    r"""Flat prior on an angle with period ``period`` (:math:`\pi` for the :math:`\phi` of
    eq 18, whose ACVF repeats every half-turn). ``u`` is the angle itself on the whole real
    line: the density ``1/period`` has no boundary, the likelihood is periodic, so the target
    is the same in every period; values are reported wrapped into
    ``[-period/2, period/2)``."""

    period: float = math.pi

    def __post_init__(self):
        check_positive("period", self.period)

    def logpdf(self, u):
        u = np.asarray(u, dtype=np.float64)
        return np.where(np.isfinite(u), -math.log(self.period), -np.inf)

    def wrap(self, angle):
        """``angle`` wrapped into ``[-period/2, period/2)``."""
        p = self.period
        return np.mod(np.asarray(angle, dtype=np.float64) + 0.5 * p, p) - 0.5 * p

    def to_natural(self, u):
        return self.wrap(u)

    def to_unconstrained(self, theta):
        return self.wrap(theta)

    def sample(self, rng, size=None):
        return as_generator(rng).uniform(-0.5 * self.period, 0.5 * self.period, size)


_PRIORS = (LogUniform, LogNormal, Uniform, UniformAngle)


@dataclasses.dataclass(frozen=True)
class Parameter:
    """One hyperparameter of a model: its ``name`` (the key of the likelihood's dict) and
    its ``prior`` (which also fixes the unconstrained parameterisation)."""

    name: str
    prior: object

    def __post_init__(self):
        if not isinstance(self.name, str) or not self.name:
            raise ValueError(f"name must be a non-empty string, got {self.name!r}")
        if not all(callable(getattr(self.prior, m, None))
                   for m in ("logpdf", "to_natural", "to_unconstrained", "sample")):
            raise ValueError(f"prior of {self.name!r} must be one of "
                             f"{', '.join(p.__name__ for p in _PRIORS)} (or provide logpdf, "
                             f"to_natural, to_unconstrained and sample), got {self.prior!r}")


@dataclasses.dataclass(frozen=True)
class PosteriorModel:
    """Parameters with priors and a log-likelihood ``log_likelihood(params: dict) -> float``.

    ``initial``: optional dict ``name -> value`` (natural units) where
    :func:`sample_posterior` starts its walkers when it is given no ``initial`` (e.g. a
    maximum-likelihood fit); ``None``: walkers start from the prior.
    """

    parameters: tuple
    log_likelihood: Callable
    initial: Mapping | None = None

    def __post_init__(self):
        params = tuple(self.parameters)
        if not params or not all(isinstance(p, Parameter) for p in params):
            raise ValueError("parameters must be a non-empty sequence of Parameter")
        names = [p.name for p in params]
        if len(set(names)) != len(names):
            raise ValueError(f"parameter names must be unique, got {names}")
        object.__setattr__(self, "parameters", params)
        if not callable(self.log_likelihood):
            raise ValueError("log_likelihood must be callable (a function of a dict of "
                             "hyperparameters)")

    @property
    def names(self) -> list[str]:
        return [p.name for p in self.parameters]

    def to_natural(self, u) -> dict:
        """Dict ``name -> value`` of the natural parameters at the unconstrained ``u``."""
        return {p.name: float(p.prior.to_natural(v)) for p, v in zip(self.parameters, u)}

    def to_unconstrained(self, values: Mapping) -> np.ndarray:
        """The unconstrained vector of a dict ``name -> value`` (natural units)."""
        missing = [n for n in self.names if n not in values]
        if missing:
            raise ValueError(f"values must give every parameter; missing {missing}")
        with np.errstate(divide="ignore", invalid="ignore"):
            u = np.array([float(p.prior.to_unconstrained(values[p.name]))
                          for p in self.parameters])
        if not np.all(np.isfinite(u)):
            bad = [n for n, v in zip(self.names, u) if not np.isfinite(v)]
            raise ValueError(f"values outside the parameters' domains (positive scales must "
                             f"be > 0): {bad}")
        return u

    def log_prior(self, u) -> float:
        """Sum of the priors' log densities in ``u`` (Jacobians included)."""
        u = np.asarray(u, dtype=np.float64)
        if u.shape != (len(self.parameters),) or not np.all(np.isfinite(u)):
            return -np.inf
        total = sum(float(p.prior.logpdf(v)) for p, v in zip(self.parameters, u))
        return total if math.isfinite(total) else -np.inf

    def log_posterior(self, u) -> float:
        """Unnormalised log posterior density in ``u``; ``-inf`` outside the priors' support
        or where the likelihood refuses the parameters (a ``ValueError``: a covariance that
        is not positive definite, an overflow); never NaN."""
        lp = self.log_prior(u)
        if not math.isfinite(lp):
            return -np.inf
        try:
            with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
                ll = float(self.log_likelihood(self.to_natural(u)))
        except (ValueError, ArithmeticError):
            return -np.inf
        if not math.isfinite(ll):
            return -np.inf
        return lp + ll


# ------------------------------------------------------------------ likelihoods

def profile_likelihood(z, spacing, acvf_fn: Callable) -> Callable:
    """Log-likelihood of a profile on a regular grid: a function of a dict of parameters.

    Args:
        z: shape (n,), zero mean (used as given: remove the mean first).
        spacing: the grid spacing (> 0).
        acvf_fn: ``acvf_fn(params, lags) -> values``: the noise-free ACVF (eq 10) at
            ``lags = spacing * arange(n)``.

    Returns:
        ``loglik(params)``; ``params["noise_variance"]``, where present, is added at lag 0
        (the white noise of eq 8). Exact, :math:`O(n^2)` per call
        (:func:`roughgp.toeplitz.toeplitz_log_likelihood`); a ``ValueError`` where the
        covariance is not positive definite.
    """
    z = np.asarray(z, dtype=np.float64)
    if z.ndim != 1 or z.size < 2:
        raise ValueError(f"z must be a profile of shape (n,) with n >= 2, got shape {z.shape}")
    check_finite("z", z)
    check_positive("spacing", spacing)
    lags = float(spacing) * np.arange(z.size, dtype=np.float64)

    def loglik(params):
        r = np.array(acvf_fn(params, lags), dtype=np.float64).reshape(-1)
        if r.shape != (z.size,):
            raise ValueError(f"acvf_fn must return {z.size} values, got shape {r.shape}")
        r[0] += params.get("noise_variance", 0.0)
        return toeplitz_log_likelihood(z, r)

    return loglik


def _check_patch(z, device=None):
    z = np.asarray(z, dtype=np.float64)
    if z.ndim != 2:
        raise ValueError(f"z must be a patch of shape (ny, nx), got shape {z.shape}")
    if device is None and z.size > MAX_GRID_POINTS:
        raise ValueError(f"z has {z.size} points ({z.shape[0]} x {z.shape[1]}); the dense "
                         f"likelihood allows at most MAX_GRID_POINTS = {MAX_GRID_POINTS} "
                         f"on the CPU (use a smaller patch, a profile with "
                         f"profile_likelihood, or device='cuda' on a GPU)")
    if device is not None:
        # the covariance, its factor and the gather's index, each N x N of 8 bytes
        check_memory(3 * 8 * z.size**2, device,
                     f"the dense likelihood of a {z.shape[0]} x {z.shape[1]} patch")
    check_finite("z", z)
    return z


def grid_likelihood(z, spacing, kernel_factory: Callable, *, device=None) -> Callable:
    """Log-likelihood of a 2-D patch (dense Cholesky, eq 12): a function of a dict.

    Args:
        z: shape (ny, nx), zero mean (used as given); on the CPU at most
            :data:`MAX_GRID_POINTS` points.
        spacing: scalar or ``(dy, dx)``, as in :func:`roughgp.sampling.grid_covariance`.
        kernel_factory: ``kernel_factory(params)`` -> a roughgp kernel or a function of lags
            of shape (..., 2) (the ACVF of eq 10, without noise).
        device: None (numpy and scipy) or a torch device such as ``"cuda"``
            (:mod:`roughgp.device`): the covariance is gathered and factorised there, and the
            patch is limited by the device's memory instead of :data:`MAX_GRID_POINTS`.

    Returns:
        ``loglik(params)``: the Gaussian log density of ``z`` with covariance
        ``grid_covariance(kernel, shape, spacing) + params["noise_variance"] * I`` (noise 0
        where absent); a ``ValueError`` where that matrix is not positive definite.
    """
    device = resolve_device(device)
    z = _check_patch(z, device)
    shape, spacing = normalize(z.shape, spacing)
    y = z.reshape(-1)
    const = 0.5 * y.size * _LOG_2PI
    not_pd = "the covariance of these hyperparameters is not positive definite on this patch"

    if device is not None:
        import torch

        y_dev = torch.as_tensor(y, device=device)

        def loglik_on_device(params):
            cov = grid_covariance(kernel_factory(params), shape, spacing, device=device)
            cov.diagonal().add_(params.get("noise_variance", 0.0))
            try:
                return float(gaussian_log_density(cov, y_dev))
            except np.linalg.LinAlgError:
                raise ValueError(not_pd) from None

        return loglik_on_device

    def loglik(params):
        cov = grid_covariance(kernel_factory(params), shape, spacing)
        cov[np.diag_indices_from(cov)] += params.get("noise_variance", 0.0)
        try:
            factor = scipy.linalg.cho_factor(cov, lower=True, check_finite=True)
        except np.linalg.LinAlgError:
            raise ValueError(not_pd) from None
        alpha = scipy.linalg.cho_solve(factor, y, check_finite=False)
        return float(-0.5 * y @ alpha - np.sum(np.log(np.diag(factor[0]))) - const)

    return loglik


# ------------------------------------------------------------------ ready-made models

def spectral_mixture_profile_model(x, z, q, *, fit=None, width=1.0) -> PosteriorModel:
    r"""Eq 21 with Q components plus white noise, for a profile ``(x, z)``.

    Parameters ``w_i``, ``mu_i``, ``v_i`` (i = 1..Q; weights, mean frequencies in cycles per
    unit of x, variances in cycles² per unit²) and ``noise_variance``. The mean of z is
    removed (as :func:`roughgp.fitting.fit_spectral_mixture` does).

    Priors: ``mu_i`` uniform on ``[0, 1/(2 dx)]`` (up to the Nyquist frequency). With a
    :class:`roughgp.fitting.SpectralMixtureFit` ``fit`` (of Q components): the scales
    log-normal around the fitted values with log-standard deviation ``width``, and the
    walkers start at the fit (``model.initial``). Without: log-uniform over wide ranges set
    by the data (weights and noise in ``[1e-6, 10] var(z)``, line widths from
    ``(0.05 / L)^2``, :data:`roughgp.fitting.MIN_LINE_WIDTH`, to ``(1 / (2 dx))^2``), walkers
    from the prior. The components are exchangeable (label switching): chains started at a
    fit keep its labels in practice; chains from the prior may not, so summarise per label
    with care.
    """
    from roughgp.fitting import MIN_LINE_WIDTH, _check_profile

    x, z, dx = _check_profile(x, z)
    if not (isinstance(q, (int, np.integer)) and q >= 1):
        raise ValueError(f"q must be an integer >= 1, got {q!r}")
    q = int(q)
    check_positive("width", width)
    z = z - z.mean()
    var = float(np.var(z))
    if not var > 0:
        raise ValueError("z must not be constant")
    nyquist = 0.5 / dx
    length = z.size * dx
    mu_prior = Uniform(0.0, nyquist)
    initial = None
    if fit is not None:
        if len(fit.weights) != q:
            raise ValueError(f"fit must have q = {q} components, got {len(fit.weights)}")
        noise = max(float(fit.noise_variance), 1e-8 * var)
        initial = {"noise_variance": noise}
        params = []
        for i in range(q):
            w, mu, v = float(fit.weights[i]), float(fit.means[i]), float(fit.variances[i])
            params += [Parameter(f"w_{i + 1}", LogNormal(math.log(w), width)),
                       Parameter(f"mu_{i + 1}", mu_prior),
                       Parameter(f"v_{i + 1}", LogNormal(math.log(v), width))]
            initial.update({f"w_{i + 1}": w, f"mu_{i + 1}": min(max(mu, 1e-9 * nyquist),
                                                                 nyquist * (1 - 1e-9)),
                            f"v_{i + 1}": v})
        params.append(Parameter("noise_variance", LogNormal(math.log(noise), width)))
    else:
        w_prior = LogUniform(1e-6 * var, 10.0 * var)
        v_prior = LogUniform((MIN_LINE_WIDTH / length) ** 2, nyquist ** 2)
        params = []
        for i in range(q):
            params += [Parameter(f"w_{i + 1}", w_prior), Parameter(f"mu_{i + 1}", mu_prior),
                       Parameter(f"v_{i + 1}", v_prior)]
        params.append(Parameter("noise_variance", LogUniform(1e-6 * var, 10.0 * var)))

    def acvf_fn(p, lags):
        out = np.zeros_like(lags)
        lag2 = lags * lags
        for i in range(1, q + 1):
            out += (p[f"w_{i}"] * np.cos(2 * math.pi * p[f"mu_{i}"] * lags)
                    * np.exp(-2 * math.pi ** 2 * p[f"v_{i}"] * lag2))
        return out

    return PosteriorModel(tuple(params), profile_likelihood(z, dx, acvf_fn), initial)


def ground_patch_model(z, spacing=1.0, *, priors: Mapping | None = None,
                       device=None) -> PosteriorModel:
    r"""Eq 18 plus white noise (eq 8) for a small ground patch ``z`` (ny, nx).

    Parameters: ``variance`` (:math:`\sigma_k^2`), ``lambda_a``, ``lambda_b``, ``angle``
    (:math:`\phi`, period :math:`\pi`) and ``noise_variance``. The mean of z is removed.
    Default priors, from the data (``var = var(z)``, ``L`` the longer side, ``d`` the finer
    spacing): ``variance`` and ``noise_variance`` log-uniform on ``[1e-6, 10] var``, the
    lengthscales log-uniform on ``[d/10, 10 L]``, the angle :class:`UniformAngle`; ``priors``
    (dict name -> prior) replaces any of them. Note :math:`(\lambda_a, \lambda_b, \phi)` and
    :math:`(\lambda_b, \lambda_a, \phi + \pi/2)` give the same ACVF, so the posterior has two
    mirrored modes unless a prior orders the lengthscales. ``device``: where the dense
    likelihood runs (:func:`grid_likelihood`); a GPU lifts the CPU's patch limit.
    """
    from roughgp import acvf as _acvf

    device = resolve_device(device)
    z = _check_patch(z, device)
    shape, sp = normalize(z.shape, spacing)
    z = z - z.mean()
    var = float(np.var(z))
    if not var > 0:
        raise ValueError("z must not be constant")
    extent = float(max(n * d for n, d in zip(shape, sp)))
    scale = LogUniform(float(sp.min()) / 10.0, 10.0 * extent)
    chosen = {"variance": LogUniform(1e-6 * var, 10.0 * var), "lambda_a": scale,
              "lambda_b": scale, "angle": UniformAngle(math.pi),
              "noise_variance": LogUniform(1e-6 * var, 10.0 * var)}
    unknown = set(priors or {}) - set(chosen)
    if unknown:
        raise ValueError(f"priors has unknown names {sorted(unknown)}; allowed: "
                         f"{list(chosen)}")
    chosen.update(priors or {})

    def kernel_factory(p):
        lengthscales = np.array([p["lambda_a"], p["lambda_b"]])
        return lambda lags: _acvf.rotated_exponential(lags, p["variance"], lengthscales,
                                                      p["angle"])

    params = tuple(Parameter(n, prior) for n, prior in chosen.items())
    return PosteriorModel(params, grid_likelihood(z, sp, kernel_factory, device=device))


def order_lengthscales(samples: Mapping, period: float = math.pi) -> dict:
    r"""Samples of eq 18 with :math:`\lambda_a \ge \lambda_b`: where a draw has
    :math:`\lambda_a < \lambda_b`, swap the two and turn the angle by a quarter turn,
    :math:`(\lambda_a, \lambda_b, \phi) \to (\lambda_b, \lambda_a, \phi + \pi/2)`, which
    is the same ACVF. Removes the mirrored mode of :func:`ground_patch_model`'s posterior.

    Args:
        samples: dict with ``"lambda_a"``, ``"lambda_b"`` and ``"angle"`` arrays (others are
            copied unchanged), e.g. :attr:`PosteriorSamples.samples`.
        period: of the angle (pi for eq 18); angles are wrapped into ``[-period/2, period/2)``.

    Returns:
        a new dict.
    """
    for name in ("lambda_a", "lambda_b", "angle"):
        if name not in samples:
            raise ValueError(f"samples must hold {name!r}, got {sorted(samples)}")
    out = {k: np.array(v, dtype=np.float64, copy=True) for k, v in samples.items()}
    swap = out["lambda_a"] < out["lambda_b"]
    out["lambda_a"][swap], out["lambda_b"][swap] = (out["lambda_b"][swap],
                                                    np.asarray(samples["lambda_a"])[swap])
    angle = out["angle"] + np.where(swap, period / 2, 0.0)
    out["angle"] = (angle + period / 2) % period - period / 2
    return out


def maximum_a_posteriori(model: "PosteriorModel", initial: Mapping, *, maxiter=5000) -> dict:
    """The posterior mode of ``model`` near ``initial`` (natural units), by Nelder-Mead in
    the unconstrained u: the optimum around which :func:`sample_posterior` starts its
    walkers (section 2.2's "optimized by maximizing", with the priors included).

    Returns:
        dict name -> value (natural units).
    """
    from scipy import optimize

    u0 = model.to_unconstrained(initial)
    if not math.isfinite(model.log_posterior(u0)):
        raise ValueError(f"initial has zero posterior density: {dict(initial)!r}")
    result = optimize.minimize(lambda u: -model.log_posterior(u), u0, method="Nelder-Mead",
                               options={"maxiter": int(maxiter), "xatol": 1e-6, "fatol": 1e-8})
    return model.to_natural(result.x)


# ------------------------------------------------------------------ sampling

class ShortChainError(ValueError):
    """The chain is too short, against its autocorrelation time, to report a posterior."""


@dataclasses.dataclass
class PosteriorSamples:
    """The result of :func:`sample_posterior`.

    ``samples``: dict name -> 1-D array of draws after burn-in (flattened over walkers,
    thinned), in natural units, angles wrapped into ``[-period/2, period/2)``;
    ``log_prob``: the log posterior (in u) of those draws; ``acceptance_fraction``: mean
    over walkers; ``autocorr_time``: dict name -> integrated autocorrelation time in steps
    (emcee, after burn-in); ``n_steps``; ``burn_in``; ``thin``; ``chain``: the whole chain
    (walkers, steps, parameters) in the unconstrained u, burn-in included;
    ``parameters``: the model's :class:`Parameter` tuple; ``walker_log_prob``: the log
    posterior of the whole chain (walkers, steps); ``walker_acceptance``: the acceptance
    fraction of each walker; ``walkers``: the indices (into the
    sampler's walkers) that ``samples`` were drawn from (all of them, unless
    :func:`main_mode` dropped some).
    """

    samples: dict
    log_prob: np.ndarray
    acceptance_fraction: float
    autocorr_time: dict
    n_steps: int
    burn_in: int
    thin: int
    chain: np.ndarray
    parameters: tuple
    walker_log_prob: np.ndarray
    walker_acceptance: np.ndarray
    walkers: tuple

    def _values(self, name):
        if name not in self.samples:
            raise ValueError(f"name must be one of {list(self.samples)}, got {name!r}")
        values = self.samples[name]
        prior = next(p.prior for p in self.parameters if p.name == name)
        if isinstance(prior, UniformAngle):  # re-centre on the circular mean: no split mode
            k = 2 * math.pi / prior.period
            centre = math.atan2(np.mean(np.sin(k * values)), np.mean(np.cos(k * values))) / k
            values = centre + prior.wrap(values - centre)
        return values

    def interval(self, name: str, level: float = 0.95) -> tuple[float, float]:
        """Central credible interval of probability ``level`` (equal tails). For an angle,
        computed in the window of one period centred on the samples' circular mean (so its
        ends may lie outside ``[-period/2, period/2)``)."""
        if not 0 < level < 1:
            raise ValueError(f"level must be in (0, 1), got {level!r}")
        lo, hi = np.quantile(self._values(name), [0.5 - level / 2, 0.5 + level / 2])
        return float(lo), float(hi)

    def summary(self) -> dict:
        """Dict name -> {median, lo68, hi68, lo95, hi95} (angles as in :meth:`interval`)."""
        out = {}
        for name in self.samples:
            v = self._values(name)
            q = np.quantile(v, [0.5, 0.16, 0.84, 0.025, 0.975])
            out[name] = dict(zip(("median", "lo68", "hi68", "lo95", "hi95"), map(float, q)))
        return out


def _initial_walkers(model, n_walkers, initial, rng, max_tries=100):
    ndim = len(model.parameters)
    if initial is not None:
        u0 = model.to_unconstrained(initial)
        if not math.isfinite(model.log_posterior(u0)):
            raise ValueError(f"initial has zero posterior density (outside a prior's support "
                             f"or a refused likelihood): {dict(initial)!r}")
        scale = 1e-3 * np.maximum(np.abs(u0), 1.0)
        draw = lambda k: u0 + scale * rng.standard_normal((k, ndim))  # noqa: E731
    else:
        draw = lambda k: np.column_stack([p.prior.sample(rng, k)  # noqa: E731
                                          for p in model.parameters])
    walkers = draw(n_walkers)
    for _ in range(max_tries):
        bad = [i for i in range(n_walkers) if not math.isfinite(model.log_posterior(walkers[i]))]
        if not bad:
            return walkers
        walkers[bad] = draw(len(bad))
    raise ValueError(f"could not start {n_walkers} walkers with finite posterior density in "
                     f"{max_tries} draws; pass initial= near a plausible value")


def sample_posterior(model: PosteriorModel, *, n_walkers=32, n_steps=2000, seed=None,
                     initial: Mapping | None = None, progress=False, burn_in=None, thin=1,
                     min_tau_multiple=50, allow_short=False) -> PosteriorSamples:
    r"""Draw from the posterior of ``model`` with emcee's ensemble sampler.

    Args:
        model: a :class:`PosteriorModel`.
        n_walkers: >= 2 x the number of parameters.
        n_steps: steps per walker (burn-in included).
        seed: int >= 0 (the same seed gives the same samples), None or a Generator.
        initial: dict name -> value (natural units): walkers start there with a relative
            scatter of 1e-3 in u; None: ``model.initial`` when set, else the prior.
        progress: emcee's progress bar.
        burn_in: steps discarded (default ``n_steps // 4``).
        thin: keep every ``thin``-th step after burn-in.
        min_tau_multiple: the chain must be at least this many times the longest
            autocorrelation time (emcee's estimate after burn-in, ``tol=0``)...
        allow_short: ...unless True (then the result is returned as is; check
            ``autocorr_time`` yourself).

    Returns:
        a :class:`PosteriorSamples`.

    Raises:
        ShortChainError: ``n_steps < min_tau_multiple * max(tau)`` and not ``allow_short``;
            the message gives n_steps, the longest tau and the length needed.
    """
    import emcee

    if not isinstance(model, PosteriorModel):
        raise ValueError(f"model must be a PosteriorModel, got {type(model).__name__}")
    ndim = len(model.parameters)
    for name, value, low in (("n_walkers", n_walkers, max(2 * ndim, 2)),
                             ("n_steps", n_steps, 2), ("thin", thin, 1)):
        check_integer(name, value, low)
    burn_in = n_steps // 4 if burn_in is None else burn_in
    if not (isinstance(burn_in, (int, np.integer)) and 0 <= burn_in < n_steps - 1):
        raise ValueError(f"burn_in must be an integer in [0, n_steps - 1) = [0, {n_steps - 1}),"
                         f" got {burn_in!r}")
    if not (isinstance(min_tau_multiple, (int, float)) and min_tau_multiple >= 0):
        raise ValueError(f"min_tau_multiple must be >= 0, got {min_tau_multiple!r}")
    rng = as_generator(seed)
    start = _initial_walkers(model, n_walkers, model.initial if initial is None else initial,
                             rng)

    sampler = emcee.EnsembleSampler(n_walkers, ndim, model.log_posterior)
    # emcee draws from its own RandomState (seeded from global entropy); seed it from ours.
    sampler.random_state = np.random.RandomState(rng.integers(2**32)).get_state()
    sampler.run_mcmc(start, n_steps, progress=progress)

    return _collect(model.parameters, np.swapaxes(sampler.get_chain(), 0, 1),
                    sampler.get_log_prob().T, sampler.acceptance_fraction,
                    tuple(range(n_walkers)), burn_in, thin, min_tau_multiple, allow_short)


def _collect(parameters, chain, walker_log_prob, acceptance, walkers, burn_in, thin,
             min_tau_multiple, allow_short) -> PosteriorSamples:
    """Autocorrelation check and natural-unit samples of ``chain`` (walkers, steps, ndim)."""
    import emcee

    names = [p.name for p in parameters]
    n_steps = chain.shape[1]
    kept = np.swapaxes(chain[:, burn_in:], 0, 1)                 # (steps, walkers, ndim)
    tau = np.atleast_1d(emcee.autocorr.integrated_time(kept, tol=0, quiet=True))
    autocorr = {n: float(t) for n, t in zip(names, tau)}
    tau_max = float(np.max(tau))
    if not allow_short and not n_steps >= min_tau_multiple * tau_max:
        raise ShortChainError(
            f"chain too short for a posterior: n_steps = {n_steps} but the longest "
            f"autocorrelation time is {tau_max:.1f} steps ({names[int(np.argmax(tau))]}); "
            f"{min_tau_multiple} x tau needs n_steps >= {math.ceil(min_tau_multiple * tau_max)}"
            f" (or pass allow_short=True)")
    flat = kept[thin - 1::thin].reshape(-1, len(names))          # emcee's thinning
    samples = {p.name: np.asarray(p.prior.to_natural(flat[:, j]), dtype=np.float64)
               for j, p in enumerate(parameters)}
    return PosteriorSamples(
        samples=samples, log_prob=walker_log_prob[:, burn_in:].T[thin - 1::thin].reshape(-1),
        acceptance_fraction=float(np.mean(acceptance)), autocorr_time=autocorr,
        n_steps=int(n_steps), burn_in=int(burn_in), thin=int(thin), chain=np.array(chain),
        parameters=tuple(parameters), walker_log_prob=np.array(walker_log_prob),
        walker_acceptance=np.array(acceptance, dtype=np.float64),
        walkers=tuple(int(w) for w in walkers))


def main_mode(result: PosteriorSamples, *, max_drop=10.0, min_tau_multiple=50,
              allow_short=False) -> PosteriorSamples:
    r"""``result`` from the walkers of its main mode only.

    An ensemble started at an optimum can lose a walker to a competing optimum of a
    multi-modal posterior (a spectral mixture's line moved to another frequency, say),
    where the stretch move cannot bring it back: its draws are not from the main mode and
    it inflates the autocorrelation times. This keeps the walkers whose median log
    posterior after burn-in is within ``max_drop`` of the best walker's median, and
    recomputes the samples, the autocorrelation times and the length check
    (:func:`sample_posterior`'s ``min_tau_multiple`` / ``allow_short``) from them. Say so
    when reporting: the result is the posterior *restricted to the main mode*.

    Raises:
        ValueError: ``max_drop`` not > 0, or fewer than two walkers would remain.
    """
    if not isinstance(result, PosteriorSamples):
        raise ValueError(f"result must be a PosteriorSamples, got {type(result).__name__}")
    check_positive("max_drop", max_drop)
    level = np.median(result.walker_log_prob[:, result.burn_in:], axis=1)
    keep = np.flatnonzero(level >= level.max() - max_drop)
    if keep.size < 2:
        raise ValueError(f"only {keep.size} walker within max_drop = {max_drop} of the best; "
                         f"raise max_drop")
    return _collect(result.parameters, result.chain[keep], result.walker_log_prob[keep],
                    result.walker_acceptance[keep], tuple(result.walkers[k] for k in keep),
                    result.burn_in, result.thin, min_tau_multiple, allow_short)
