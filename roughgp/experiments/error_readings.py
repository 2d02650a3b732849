r"""Every reading of section 3.1's error experiment that the book tried, with its expected value.

Section 3.1: "we sampled 50 latent ground surfaces each with :math:`100 \times 100` points and
hyperparameters according to figure 2. Then, we computed the mean absolute error between the
given covariance matrix and the unbiased sample covariance matrix element-wise" (Cholesky
0.2536, Lanczos 0.2763). The setup leaves choices open: the coordinates (grid units, or the
unit square, where figure 1's lengthscales (0.5, 0.1) live), latent or noisy heights (eq 8,
:math:`\sigma^2 = 1`), the estimator (``ddof``, a known mean), the number of draws and the
variance. :func:`readings` gives the exact sampler's expected error for each.

The expectation is a lag sum over the stationary grid covariance (R of eq 10 from eq 18): each
entry of the sample covariance is close to normal (a sum of ``n - 1`` products, Wishart) with
:math:`\operatorname{Var}(S_{ij}) = (R_{ij}^2 + R_{ii}R_{jj})/\nu` and a bias :math:`\mu`
(:math:`-R_{ij}/n` for ``ddof = 0``, :math:`\sigma^2` on the diagonal when noisy heights are
compared with the latent R), so :math:`\mathbb E|S_{ij}-R_{ij}|` is the folded normal mean
:math:`s\sqrt{2/\pi}\,e^{-\mu^2/2s^2} + \mu(1 - 2\Phi(-\mu/s))`; the mean over all
:math:`N^2` pairs counts each lag :math:`(n_y - |k_y|)(n_x - |k_x|)` times. With the stated
setup it equals :func:`roughgp.sampling.diagnostics.expected_covariance_error` of the dense R.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
from scipy import stats

from roughgp.experiments.surface_errors import N_DRAWS, NOISE_VARIANCE, PAPER_ERROR, SHAPE
from roughgp.models import surfaces

__all__ = ["ESTIMATORS", "Reading", "expected_error", "readings"]

ESTIMATORS = ("unbiased", "ddof=0", "known mean")
"""The sample covariances: mean removed and / (n - 1) (the paper's), mean removed and / n,
no mean removed and / n (the draws' zero mean taken as known)."""

FIGURE_1_LENGTHSCALES = (0.5, 0.1)     # figure 1's, on the unit square (fig1-acvf)


@dataclasses.dataclass(frozen=True)
class Reading:
    """One reading of the setup: what it changes (``label``), its settings and the exact
    sampler's expected mean absolute error; ``ratio``: that over the paper's Cholesky value."""

    label: str
    variance: float
    lengthscales: tuple
    spacing: float
    heights: str                 # "latent", "noisy vs R + sigma^2 I", "noisy vs latent R"
    estimator: str
    n_draws: int
    expected: float

    @property
    def ratio(self) -> float:
        return self.expected / PAPER_ERROR["cholesky"]


def _folded_normal_mean(mu, sd):
    sd = np.maximum(sd, 1e-300)
    return (sd * math.sqrt(2 / math.pi) * np.exp(-0.5 * (mu / sd) ** 2)
            + mu * (1 - 2 * stats.norm.cdf(-mu / sd)))


def expected_error(parameters: surfaces.GrooveParameters, shape=SHAPE, n_draws: int = N_DRAWS,
                   *, spacing: float = 1.0, noise_variance: float = 0.0,
                   noisy_target: bool = True, estimator: str = "unbiased") -> float:
    """The exact sampler's expected mean absolute covariance error of section 3.1.

    Args:
        parameters: eq 18's hyperparameters (lengthscales in the unit of ``spacing``).
        shape: the grid ``(n_y, n_x)``; ``spacing``: its step.
        n_draws: the number of surfaces (>= 2).
        noise_variance: :math:`\\sigma^2` of eq 8 added to the draws (0: latent heights).
        noisy_target: compare with R + :math:`\\sigma^2` I (True) or with the latent R.
        estimator: one of :data:`ESTIMATORS`.
    """
    if estimator not in ESTIMATORS:
        raise ValueError(f"estimator must be one of {ESTIMATORS}, got {estimator!r}")
    n = int(n_draws)
    if n < 2:
        raise ValueError(f"n_draws must be an integer >= 2, got {n_draws!r}")
    ny, nx = (int(v) for v in shape)
    ky, kx = np.mgrid[-(ny - 1):ny, -(nx - 1):nx]
    counts = (ny - np.abs(ky)) * (nx - np.abs(kx))
    lags = np.stack([kx, ky], axis=-1) * float(spacing)
    r = np.asarray(parameters.kernel().acvf(lags), dtype=np.float64)
    at_zero = (ky == 0) & (kx == 0)
    r_drawn = r + noise_variance * at_zero             # the draws' covariance
    d = parameters.variance + noise_variance           # its diagonal
    target = r_drawn if noisy_target else r
    moments = r_drawn ** 2 + d ** 2
    if estimator == "unbiased":
        mean, var = r_drawn, moments / (n - 1)
    elif estimator == "ddof=0":
        mean, var = r_drawn * (n - 1) / n, moments * (n - 1) / n ** 2
    else:
        mean, var = r_drawn, moments / n
    error = _folded_normal_mean(mean - target, np.sqrt(var))
    return float(np.sum(counts * error) / float(ny * nx) ** 2)


def readings(parameters: surfaces.GrooveParameters = surfaces.FIGURE_2, shape=SHAPE,
             n_draws: int = N_DRAWS, noise_variance: float = NOISE_VARIANCE) -> list[Reading]:
    """The readings tried, as stated first; each changes one or two things of the setup."""
    p, sigma2 = parameters, float(noise_variance)
    unit = surfaces.GrooveParameters(1.0, p.lengthscales, p.angle)
    fig1 = surfaces.GrooveParameters(p.variance, FIGURE_1_LENGTHSCALES, p.angle)
    fig1_unit = surfaces.GrooveParameters(1.0, FIGURE_1_LENGTHSCALES, p.angle)
    square = 1.0 / (shape[1] - 1)                      # the unit square, 100 points a side
    domain = (surfaces.FIGURE_2_SHAPE[1] - 1) / (shape[1] - 1)   # figure 2's 2000 points
    noisy, latent_target = "noisy vs R + sigma^2 I", "noisy vs latent R"
    cases = [
        ("as stated: grid units, latent, unbiased", p, 1.0, "latent", "unbiased", n_draws),
        ("estimator / n (ddof = 0)", p, 1.0, "latent", "ddof=0", n_draws),
        ("known zero mean, / n", p, 1.0, "latent", "known mean", n_draws),
        ("noisy heights (eq 8), R + sigma^2 I", p, 1.0, noisy, "unbiased", n_draws),
        ("noisy heights against the latent R", p, 1.0, latent_target, "unbiased", n_draws),
        ("sigma_k^2 = 1", unit, 1.0, "latent", "unbiased", n_draws),
        ("sigma_k^2 = 1, noisy heights", unit, 1.0, noisy, "unbiased", n_draws),
        ("sigma_k^2 = 1, 100 draws", unit, 1.0, "latent", "unbiased", 2 * n_draws),
        ("100 draws", p, 1.0, "latent", "unbiased", 2 * n_draws),
        ("1000 draws", p, 1.0, "latent", "unbiased", 20 * n_draws),
        ("unit square (lambda 500, 5 on [0, 1])", p, square, "latent", "unbiased", n_draws),
        ("unit square, figure 1's lambda (0.5, 0.1)", fig1, square, "latent", "unbiased",
         n_draws),
        ("unit square, figure 1's lambda, sigma_k^2 = 1", fig1_unit, square, "latent",
         "unbiased", n_draws),
        ("100 points over figure 2's 2000 (step 20.2)", p, domain, "latent", "unbiased",
         n_draws),
        ("step 20.2, noisy heights", p, domain, noisy, "unbiased", n_draws),
    ]
    out = []
    for label, params, spacing, heights, estimator, draws in cases:
        value = expected_error(params, shape, draws, spacing=spacing,
                               noise_variance=0.0 if heights == "latent" else sigma2,
                               noisy_target=heights != latent_target, estimator=estimator)
        out.append(Reading(label, float(params.variance), tuple(params.lengthscales),
                           float(spacing), heights, estimator, int(draws), value))
    return out
