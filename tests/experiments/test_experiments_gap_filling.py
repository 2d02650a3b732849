"""Tests of roughgp.experiments.gap_filling (the chapter "Filling unmeasured points" and the
ledger's future-gap-filling claim share it)."""

import math

import numpy as np
import pytest

from roughgp.experiments import gap_filling as experiment


def test_scenario_holes_are_disjoint_and_placed():
    s = experiment.gap_scenario(64, seed=3)
    h = s.holes
    assert not np.any(h["scratch"] & h["blob"]) and not np.any(h["dropouts"] & (h["scratch"] | h["blob"]))
    assert np.array_equal(s.missing, np.isnan(s.measured))
    assert np.all(h["scratch"][int(0.72 * 64)]) and h["scratch"].sum() == 3 * 64
    assert h["blob"][int(0.3 * 64), int(0.3 * 64)]
    assert 0.05 < h["dropouts"].mean() < 0.15
    assert 0.0 < np.std(s.z - s.latent) < 1.0                 # the noise of eq 8, sd ~ 0.32
    again = experiment.gap_scenario(64, seed=3)
    assert np.array_equal(again.latent, s.latent) and np.array_equal(again.missing, s.missing)


def test_baseline_is_exact_on_a_plane():
    iy, ix = np.indices((40, 40))
    z = 0.5 * iy - 0.25 * ix + 1.0
    missing = np.zeros(z.shape, dtype=bool)
    missing[18:22, 15:25] = True
    base = experiment.interpolate_baseline(z, missing, np.s_[10:30, 10:30], margin=4)
    assert base.evaluate.sum() == missing.sum() and base.n_window == 400
    truth = z[base.evaluate]
    for method in ("linear", "cubic"):
        np.testing.assert_allclose(base.values[method], truth, atol=1e-8)
    assert np.max(np.abs(base.values["nearest"] - truth)) > 0.1   # nearest is not exact


def test_expected_coverage_is_students_t():
    assert experiment.expected_coverage(16) == pytest.approx(0.937, abs=5e-4)
    assert experiment.expected_coverage(1e6) == pytest.approx(0.9545, abs=1e-3)


def test_small_comparison_beats_interpolation_and_is_calibrated():
    result = experiment.compare_gap_filling(
        64, n_samples=8, fit_options=dict(block=12, n_blocks=6, maxiter=300))
    assert result.n == 64 and set(result.fills) == {"known", "fitted"}
    assert result.fills["known"].converged      # (a 64 x 64 fit may get sigma^2 ~ 0: slow CG)
    assert set(result.window_rmse) == {"GP", "nearest", "linear", "cubic"}
    assert result.window_rmse["GP"]["all"] < min(result.window_rmse[m]["all"]
                                                 for m in experiment.INTERPOLANTS)
    prior_sd = math.sqrt(experiment.GROUND.variance)
    assert 0.0 < result.rmse["known"]["dropouts"] < result.rmse["known"]["blob"] < 1.5 * prior_sd
    for label in ("known", "fitted"):
        assert 0.75 <= result.coverage[label]["all"] <= 1.0
    assert result.expected_coverage == pytest.approx(experiment.expected_coverage(8))
