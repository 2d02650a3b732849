r"""Priors of GP hyperparameters in an unconstrained parameterisation, and the posterior model (section 2.2).

The sampler works in an unconstrained parameter ``u``: ``u = log(theta)`` for positive
scales (:class:`LogUniform`, :class:`LogNormal`), ``u = theta`` for a bounded
:class:`Uniform` or for an angle (:class:`UniformAngle`). Every prior's ``logpdf`` is the
density *in u* (the Jacobian of the transform included), so

.. math::
    \log p(u \mid z) = \log p(z \mid \theta(u)) + \sum_j \log p_j(u_j) + \text{const}.

A :class:`PosteriorModel` is a list of :class:`Parameter` (a name and a prior) and a
log-likelihood, a function of a dict ``name -> value`` in natural units.
"""

from __future__ import annotations

import dataclasses
import math
from typing import Callable, Mapping

import numpy as np

from roughgp.common.checks import as_generator, check_finite, check_positive

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
