r"""Section 2.3's relations between ARMA processes and GPs (eq 12-17), and figure 1's ridge.

Each function computes what the chapter ``arma`` (or ``notation``, for figure 1) shows and the
ledger's check of the same claim judges, so the two state one computation:

* :func:`ma_finite` -- an MA(q) is a linear process (eq 13) with finitely many weights, its
  ACVF zero beyond lag q (check ``sec2.3-ma-finite``);
* :func:`arma_truncation` -- a stationary ARMA is a causal linear process (eq 14): the MA(K)
  of its first K weights converges to its ACVF (check ``sec2.3-arma-linear``);
* :func:`sampled_gp_as_arma` -- the sampled exponential kernel is an AR(1), the sampled
  Matérn 3/2 an ARMA(2, 1), exactly (check ``sec2.3-gp-is-arma``);
* :func:`negative_ar1` -- an AR(1) with a < 0 alternates and maps to no OU process
  (check ``sec2.3-ar-not-gp``);
* :func:`feature_maps` -- eq 16-17: a feature map's autocorrelation is the kernel; the Riemann
  sum on a grid of step h, and the one-sided exponential map as an AR(1)
  (check ``eq16-17-moving-average``);
* :func:`figure1_ridge` -- figure 1's rotated exponential (eq 18): the direction of slowest
  decay and the 1/e distances along and across (chapter ``notation``, check ``fig1-acvf``).

Each returns a dataclass; every ACVF is exact (:func:`roughgp.models.arma.arma_acvf`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from roughgp.gp import kernels
from roughgp.models import arma, moving_average

__all__ = ["MaFinite", "ma_finite", "ArmaTruncation", "arma_truncation", "SampledGP",
           "sampled_gp_as_arma", "NegativeAR1", "negative_ar1", "FeatureMaps", "feature_maps",
           "Figure1Ridge", "figure1_ridge"]


@dataclass
class MaFinite:
    """An MA(q) as a linear process: its weights, exact ACVF and the ACVF from the weights."""

    ma: tuple
    sigma2: float
    weights: np.ndarray          # beta_0 .. beta_nlags
    acvf: np.ndarray             # lags 0 .. nlags - 1 (arma_acvf)
    from_weights: np.ndarray     # sigma^2 sum_k beta_k beta_{k+h}
    gap: float                   # max |from_weights - acvf|
    weights_beyond_q: float      # max |beta_k|, k > q
    acvf_beyond_q: float         # max |r(h)|, h > q


def ma_finite(ma=(0.5, -0.3, 0.2), sigma2=1.0, nlags=10):
    """Eq 13 for the MA(q) with coefficients ``ma``: weights, ACVF, and both beyond q."""
    q = len(ma)
    weights = arma.linear_process_weights([], list(ma), nlags)
    from_weights = arma.acvf_from_weights(weights, sigma2, nlags)
    exact = arma.arma_acvf([], list(ma), sigma2, nlags)
    return MaFinite(tuple(ma), sigma2, weights, exact, from_weights,
                    float(np.abs(from_weights - exact).max()),
                    float(np.abs(weights[q + 1:]).max()), float(np.abs(exact[q + 1:]).max()))


@dataclass
class ArmaTruncation:
    """The causal weights of a stationary ARMA and the MA(K) truncations' ACVF errors."""

    ar: tuple
    ma: tuple
    sigma2: float
    acvf: np.ndarray             # exact, lags 0 .. nlags - 1
    weights: np.ndarray          # the first n_weights causal weights (eq 14)
    truncations: tuple
    errors: list                 # max |MA(K) ACVF - acvf| per K of truncations


def arma_truncation(ar=(1.2, -0.5), ma=(0.4,), sigma2=1.0, nlags=40,
                    truncations=(5, 10, 20, 40, 60, 80), n_weights=30):
    """Eq 14 for the ARMA(``ar``, ``ma``): the MA(K) of its first K causal weights against
    its exact ACVF over ``nlags`` lags, for each K of ``truncations``."""
    exact = arma.arma_acvf(list(ar), list(ma), sigma2, nlags)
    errors = []
    for k in truncations:
        w = arma.linear_process_weights(list(ar), list(ma), k)
        errors.append(float(np.abs(arma.acvf_from_weights(w, sigma2, nlags) - exact).max()))
    return ArmaTruncation(tuple(ar), tuple(ma), sigma2, exact,
                          arma.linear_process_weights(list(ar), list(ma), n_weights),
                          tuple(truncations), errors)


@dataclass
class SampledGP:
    """The exponential kernel as an AR(1) and the Matérn 3/2 as an ARMA(2, 1), sampled."""

    variance: float
    lengthscale: float
    spacing: float
    exponential: object          # MaternKernel(nu=0.5)
    matern32: object             # MaternKernel(nu=1.5)
    ar1: tuple                   # (ar, ma, sigma2) of arma.ou_to_ar1
    arma21: tuple                # (ar, ma, sigma2) of arma.matern32_to_arma21
    gap_ou: float                # max |AR(1) ACVF - exponential| over the lags
    gap_m32: float               # max |ARMA(2, 1) ACVF - Matern 3/2|


def sampled_gp_as_arma(variance=2.0, lengthscale=5.0, spacing=1.0, nlags=60):
    """Eq 15: both kernels (``variance``, ``lengthscale``) sampled at ``spacing``, their
    discrete ARMA and the largest ACVF gap over ``nlags`` lags (absolute, height²)."""
    lags = spacing * np.arange(float(nlags))[:, None]
    exponential = kernels.MaternKernel(nu=0.5, variance=variance, lengthscale=lengthscale)
    matern32 = kernels.MaternKernel(nu=1.5, variance=variance, lengthscale=lengthscale)
    ar1 = arma.ou_to_ar1(variance, lengthscale, spacing)
    arma21 = arma.matern32_to_arma21(variance, lengthscale, spacing)
    gap_ou = float(np.abs(arma.arma_acvf(*ar1, nlags=nlags) - exponential.acvf(lags)).max())
    gap_m32 = float(np.abs(arma.arma_acvf(*arma21, nlags=nlags) - matern32.acvf(lags)).max())
    return SampledGP(variance, lengthscale, spacing, exponential, matern32, ar1, arma21,
                     gap_ou, gap_m32)


@dataclass
class NegativeAR1:
    """An AR(1) with a negative coefficient: its ACVF, and whether an OU process maps to it."""

    a: float
    acvf: np.ndarray
    alternates: bool             # signs +, -, +, ... at lags 0, 1, 2, ...
    refusal: str                 # arma.ar1_to_ou's message ("" if it did not refuse)


def negative_ar1(a=-0.6, sigma2=1.0, spacing=1.0, nlags=8):
    """The converse of eq 15 fails: the AR(1) of coefficient ``a`` < 0 is no sampled OU."""
    r = arma.arma_acvf([a], [], sigma2, nlags)
    try:
        arma.ar1_to_ou(a, sigma2, spacing)
        refusal = ""
    except ValueError as error:
        refusal = str(error)
    return NegativeAR1(a, r, bool(np.all(np.sign(r) == (-1.0) ** np.arange(nlags))), refusal)


@dataclass
class FeatureMaps:
    """Eq 16-17 on grids of step h: the Riemann sum's error per feature map and step, and the
    discretised one-sided exponential map against the AR(1) of a = exp(-h / lambda)."""

    maps: tuple                  # (Gaussian, one-sided exponential) feature maps
    steps: tuple
    errors: dict                 # map name -> max |eq 17 on the grid - kernel| per step
    ar1_step: float
    ar1_gap: float               # max |discretised one-sided MA ACVF - AR(1) ACVF|

    @property
    def gaussian_errors(self):
        return self.errors[self.maps[0].name]

    @property
    def exponential_errors(self):
        return self.errors[self.maps[1].name]


def feature_maps(variance=2.0, lengthscale=5.0, steps=(1.0, 0.5, 0.25, 0.125), extent=40.0,
                 ar1_step=0.5, ar1_lags=30):
    """The Gaussian and the one-sided exponential feature map (``variance``, ``lengthscale``):
    eq 17 on lags up to ``extent`` for each step h, and at ``ar1_step`` the discretised
    one-sided map against the AR(1) with innovations c sqrt(h), c² = 2 sigma² / lambda."""
    gaussian = moving_average.gaussian_feature_map(variance=variance, lengthscale=lengthscale)
    one_sided = moving_average.exponential_feature_map(variance=variance,
                                                       lengthscale=lengthscale)
    errors = {}
    for fm in (gaussian, one_sided):
        errors[fm.name] = [float(np.abs(moving_average.feature_map_acvf(fm, int(extent / h), h)
                                        - fm.kernel(h * np.arange(int(extent / h)))).max())
                           for h in steps]
    h = ar1_step
    discrete_ma = moving_average.feature_map_acvf(one_sided, ar1_lags, h)
    as_ar1 = arma.arma_acvf([math.exp(-h / lengthscale)], [], (2 * variance / lengthscale) * h,
                            ar1_lags)
    return FeatureMaps((gaussian, one_sided), tuple(steps), errors, h,
                       float(np.abs(discrete_ma - as_ar1).max()))


@dataclass
class Figure1Ridge:
    """Figure 1 (eq 18): the direction of slowest decay at ``distance`` and r at lambda_a
    along phi and at lambda_b across it."""

    kernel: object               # RotatedExponentialKernel
    distance: float
    slowest_deg: float
    along: float                 # r(lambda_a along phi), should be sigma_k^2 / e
    across: float                # r(lambda_b across phi)


def figure1_ridge(variance=1.0, lengthscales=(0.5, 0.1), angle=math.pi / 6, distance=0.3,
                  step_deg=0.1):
    """Figure 1's ACVF: the direction (0..180 deg in steps of ``step_deg``) in which it
    decays slowest at ``distance``, and its values at the lengthscales along and across."""
    kernel = kernels.RotatedExponentialKernel(variance=variance, lengthscales=lengthscales,
                                              angle=angle)
    directions = np.deg2rad(np.arange(0, 180, step_deg))
    unit = np.stack([np.cos(directions), np.sin(directions)], axis=-1)
    slowest = float(np.rad2deg(directions[np.argmax(kernel.acvf(distance * unit))]))
    along_dir = np.array([[math.cos(angle), math.sin(angle)]])
    across_dir = np.array([[-math.sin(angle), math.cos(angle)]])
    along = float(kernel.acvf(lengthscales[0] * along_dir)[0])
    across = float(kernel.acvf(lengthscales[1] * across_dir)[0])
    return Figure1Ridge(kernel, distance, slowest, along, across)
