r"""Gap filling against classical interpolation (beyond the paper; its conclusion, ref [48]).

The paper's conclusion notes that optical instruments leave non-measured points and that the GP
model can interpolate them. This module is the one computation behind the book's chapter
"Filling unmeasured points" and the ledger's claim ``future-gap-filling``:

* :func:`gap_scenario`: a ground surface of eq 18 (latent :math:`g`) and its measurement
  :math:`z = g + \varepsilon` (eq 8), with three kinds of holes: scattered dropouts, a scratch
  (a line 3 points wide across the surface) and a blob (an ellipse, like a steep flank);
* :func:`~roughgp.filling.interpolants.interpolate_baseline` (imported here): nearest, linear
  (Delaunay) and cubic (Clough-Tocher) interpolation of the measured points, restricted to a
  window (a Delaunay triangulation of a regular grid is slow);
* :func:`compare_gap_filling`: the GP posterior mean and sd
  (:func:`roughgp.filling.global_fill.fill_gaps`) with the known hyperparameters and with those
  fitted to the measured points alone (:func:`roughgp.inference.block_fit.fit_ground_to_valid_points`,
  eq 18 plus the noise of eq 8), scored by the RMSE against :math:`g` per hole type and by the
  share of the truth inside :math:`\pm 2` posterior sd. It returns a :class:`GapFillingResult`.

The sd is a Monte Carlo estimate from ``n_samples`` pathwise draws, so
:math:`(g - \bar g)/\mathrm{sd}` is Student-:math:`t` with ``n_samples`` degrees of freedom:
:func:`expected_coverage` gives the share expected inside :math:`\pm 2` sd.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np
import scipy.stats

from roughgp.common.checks import check_integer
from roughgp.filling.global_fill import GapFill, fill_gaps
from roughgp.filling.interpolants import INTERPOLANTS, Baseline, interpolate_baseline
from roughgp.inference.block_fit import BlockFit, fit_ground_to_valid_points
from roughgp.models import surfaces

__all__ = ["GROUND", "NOISE_VARIANCE", "DROPOUT_SHARE", "N_SAMPLES", "SEED", "WINDOW",
           "INTERPOLANTS", "GapScenario", "Baseline", "GapFillingResult", "gap_scenario",
           "window_slices", "interpolate_baseline",
           "rmse_by_region", "coverage_by_region", "expected_coverage", "compare_gap_filling"]

#: The simulated ground surface (eq 18): sigma_k^2 = 10, lambda_a = 40, lambda_b = 5, phi = pi/6.
GROUND = surfaces.GrooveParameters(variance=10.0, lengthscales=(40.0, 5.0), angle=math.pi / 6)
NOISE_VARIANCE = 0.1        #: sigma^2 of eq 8
DROPOUT_SHARE = 0.10        #: share of scattered single-point dropouts
N_SAMPLES = 16              #: pathwise draws for the posterior sd
SEED = 11
#: Where the interpolants are compared: (row, column) ranges as shares of the grid side.
WINDOW = ((0.2, 0.8), (0.15, 0.55))


@dataclass(frozen=True)
class GapScenario:
    """A surface with known truth and holes (:func:`gap_scenario`).

    Attributes:
        latent: the latent surface :math:`g` (eq 18), ``(n, n)``.
        z: the measurement :math:`g + \\varepsilon` (eq 8) on the whole grid.
        holes: boolean maps ``{"scratch", "blob", "dropouts"}`` (disjoint).
        missing: the union of the holes.
        measured: ``z`` with NaN at the missing points (what the fill sees).
        ground: the simulated eq 18 hyperparameters.
        noise_variance: the simulated :math:`\\sigma^2`.
    """

    latent: np.ndarray
    z: np.ndarray
    holes: dict
    missing: np.ndarray
    measured: np.ndarray
    ground: surfaces.GrooveParameters
    noise_variance: float


@dataclass(frozen=True)
class GapFillingResult:
    """The comparison of :func:`compare_gap_filling`.

    Attributes:
        scenario: the surface and its holes.
        fills: ``{"known", "fitted"}`` -> :class:`~roughgp.filling.global_fill.GapFill`.
        fitted: the block composite-likelihood fit on the measured points.
        baseline: the interpolants in the window.
        window_rmse: ``{"GP", "nearest", "linear", "cubic"}`` -> ``{hole kind, "all"}`` -> RMSE
            against :math:`g` over the window's missing points ("GP": known hyperparameters).
        rmse: ``{"known", "fitted"}`` -> ``{hole kind, "all"}`` -> RMSE over the whole grid.
        coverage: ``{"known", "fitted"}`` -> ``{hole kind, "all"}`` -> share of the missing
            points with :math:`|g - \\bar g| \\le 2\\,\\mathrm{sd}`.
        mean_squared_z: ``{"known", "fitted"}`` -> mean of :math:`(g - \\bar g)^2/\\mathrm{sd}^2`.
        expected_coverage: :math:`P(|t_\\nu| < 2)` for ``nu = n_samples``.
        n_samples: pathwise draws behind the sd.
    """

    scenario: GapScenario
    fills: dict
    fitted: BlockFit
    baseline: Baseline
    window_rmse: dict
    rmse: dict
    coverage: dict
    mean_squared_z: dict
    expected_coverage: float
    n_samples: int

    @property
    def n(self) -> int:
        """The grid side."""
        return self.scenario.latent.shape[0]


def gap_scenario(n, *, seed=SEED, ground=GROUND, noise_variance=NOISE_VARIANCE,
                 dropout_share=DROPOUT_SHARE) -> GapScenario:
    """An ``n`` x ``n`` ground surface (eq 18) and its measurement (eq 8, same ``seed``) with a
    scratch (3 rows at 0.72 n), a blob (ellipse centred at (0.3 n, 0.3 n), semi-axes 0.09 n
    along x and 0.05 n along y) and dropouts (share ``dropout_share`` elsewhere, seed
    ``seed + 1``)."""
    seed = check_integer("seed", seed, 0)
    n = check_integer("n", n, 16)
    shape = (n, n)
    params = dataclasses.asdict(ground)
    g = surfaces.ground(shape, **params, noise_variance=0.0, seed=seed, latent=True)
    z = surfaces.ground(shape, **params, noise_variance=noise_variance, seed=seed)
    iy, ix = np.indices(shape)
    holes = {"scratch": np.abs(iy - int(0.72 * n)) <= 1,
             "blob": ((ix - 0.3 * n) / (0.09 * n)) ** 2 + ((iy - 0.3 * n) / (0.05 * n)) ** 2 <= 1}
    dropouts = np.random.default_rng(seed + 1).random(shape) < dropout_share
    holes["dropouts"] = dropouts & ~holes["scratch"] & ~holes["blob"]
    missing = holes["scratch"] | holes["blob"] | holes["dropouts"]
    return GapScenario(g, z, holes, missing, np.where(missing, np.nan, z), ground,
                       float(noise_variance))


def window_slices(n, window=WINDOW):
    """The window ``((r0, r1), (c0, c1))`` (shares of the side) as a pair of slices."""
    (r0, r1), (c0, c1) = window
    return np.s_[int(r0 * n):int(r1 * n), int(c0 * n):int(c1 * n)]


def rmse_by_region(estimate, truth, regions):
    """``{name: RMSE of estimate - truth over the region}`` for boolean maps ``regions``."""
    return {name: float(np.sqrt(np.mean((estimate - truth)[r] ** 2))) for name, r in regions.items()}


def coverage_by_region(fill: GapFill, truth, regions, *, k=2.0):
    """``{name: share of the region's points with |truth - mean| <= k sd}``."""
    inside = np.abs(truth - fill.mean) <= k * fill.sd
    return {name: float(np.mean(inside[r])) for name, r in regions.items()}


def expected_coverage(nu, k=2.0) -> float:
    """:math:`P(|t_\\nu| < k)`: the share inside :math:`\\pm k` sd when the sd is estimated
    from ``nu`` draws."""
    return float(1 - 2 * scipy.stats.t.sf(k, df=nu))


def _window_rmse(scenario, baseline, gp_mean):
    truth = scenario.latent[baseline.evaluate]
    kinds = {name: h[baseline.evaluate] for name, h in scenario.holes.items()}
    kinds["all"] = np.ones(truth.shape, dtype=bool)
    estimates = {"GP": gp_mean[baseline.evaluate], **baseline.values}
    return {m: rmse_by_region(f, truth, kinds) for m, f in estimates.items()}


def compare_gap_filling(n=256, *, seed=SEED, ground=GROUND, noise_variance=NOISE_VARIANCE,
                        dropout_share=DROPOUT_SHARE, n_samples=N_SAMPLES, window=WINDOW,
                        margin=12, fit_options=None) -> GapFillingResult:
    """Fill the holes of :func:`gap_scenario` with the GP, once with the known
    hyperparameters and once with those fitted on the measured points, and score both against
    the truth and against :func:`interpolate_baseline` in ``window``. Every random draw
    (surface, noise, dropouts, the fit's blocks, the pathwise draws) follows ``seed``;
    ``fit_options`` (e.g. ``block``, ``n_blocks``, ``maxiter``) go to the fit."""
    scenario = gap_scenario(n, seed=seed, ground=ground, noise_variance=noise_variance,
                            dropout_share=dropout_share)
    measured = scenario.measured
    known = fill_gaps(measured, ground.kernel(), noise_variance=noise_variance,
                      n_samples=n_samples, seed=seed)
    baseline = interpolate_baseline(scenario.z, scenario.missing, window_slices(n, window),
                                    margin=margin)
    fitted = fit_ground_to_valid_points(measured, seed=seed, **(fit_options or {}))
    fills = {"known": known,
             "fitted": fill_gaps(measured, fitted.kernel, noise_variance=fitted.noise_variance,
                                 n_samples=n_samples, seed=seed)}
    regions = {**scenario.holes, "all": scenario.missing}
    g = scenario.latent
    missing = scenario.missing
    return GapFillingResult(
        scenario=scenario, fills=fills, fitted=fitted, baseline=baseline,
        window_rmse=_window_rmse(scenario, baseline, known.mean),
        rmse={k: rmse_by_region(f.mean, g, regions) for k, f in fills.items()},
        coverage={k: coverage_by_region(f, g, regions) for k, f in fills.items()},
        mean_squared_z={k: float(np.mean((g - f.mean)[missing] ** 2 / f.sd[missing] ** 2))
                        for k, f in fills.items()},
        expected_coverage=expected_coverage(n_samples), n_samples=int(n_samples))
