"""The calibrated model check (issue 29, step 2): the randomised p-value is uniform for
exchangeable extremeness counts (so its level is exact, where the plain count is not), the
refit repeats the fit, and the check's plain part is ``check_model``'s."""

from __future__ import annotations

import dataclasses
import json

import numpy as np
import pytest

from roughgp.checking import calibrated as cc
from roughgp.checking.model_check import check_model
from roughgp.experiments.model_check import synthetic_measurement
from roughgp.surface_models.fit import fit_surface_model


def test_the_randomised_p_value_has_the_exact_level_where_the_plain_count_has_not():
    """Extremeness counts are discrete (0 .. 9 of 19 simulations, most mass at the ends for a
    fitted model): drawn independently from one such law, the measurement's and B = 19 copies',
    p <= 0.1 happens in 10 % of the trials, and the outside chance has the same mean; counting
    only strictly smaller copies (no tie-breaking) would be far off."""
    rng = np.random.default_rng(0)
    law = np.array([0.065, 0.1, 0.1, 0.1, 0.1, 0.1, 0.1, 0.1, 0.1, 0.135])
    trials = 20000
    counts = rng.choice(10, size=(trials, 20), p=law).astype(float)
    u = rng.random(trials)
    p = np.array([cc.calibrated_p(row[0], row[1:], ui) for row, ui in zip(counts, u)])
    chance = np.array([cc.outside_chance(row[0], row[1:]) for row in counts])
    assert abs(np.mean(p <= 0.1) - 0.1) < 0.006  # 3 sd of a 20000-trial share
    assert abs(chance.mean() - 0.1) < 0.004
    strict = np.array([np.sum(row[1:] < row[0]) / 20 for row in counts])
    assert np.mean(strict <= 0.1) > 0.2  # ties make the untied count far from 10 %


def test_the_p_value_of_edge_cases():
    assert cc.calibrated_p(0.0, [0.0] * 19, 0.5) == pytest.approx(0.5)
    assert cc.calibrated_p(9.0, [0.0] * 19, 0.0) == pytest.approx(19 / 20)
    assert cc.calibrated_p(0.0, [3.0] * 19, 0.99) == pytest.approx(0.99 / 20)
    assert np.isnan(cc.calibrated_p(np.nan, [1.0, 2.0], 0.5))
    assert np.isnan(cc.calibrated_p(1.0, [np.nan, np.nan], 0.5))
    assert cc.outside_chance(0.0, [3.0] * 19) == 1.0
    assert cc.outside_chance(9.0, [0.0] * 19) == 0.0
    assert cc.outside_chance(0.0, [0.0] * 19) == pytest.approx(0.1)  # 2 of 20 places


@pytest.fixture(scope="module")
def fitted_case():
    truth, l_filter, z = synthetic_measurement(3, (40, 40), 0)
    model = fit_surface_model(z, 1.0, l=l_filter, block=12, n_blocks=6, seed=5).model
    return model, z


def test_the_refit_repeats_the_fit_on_the_same_heights(fitted_case):
    model, z = fitted_case
    again = cc.refit_like(model, z)
    assert again.equation == model.equation and again.cutoffs == model.cutoffs
    for key, value in model.hyperparameters.items():
        assert again.hyperparameters[key] == pytest.approx(value, rel=1e-9), key
    assert again.fit["block"] == 12 and again.fit["seed"] == 5


def test_a_model_the_check_cannot_refit_is_refused_before_any_work(fitted_case):
    model, z = fitted_case
    filtered = dataclasses.replace(model, stage="filtered")
    with pytest.raises(ValueError, match="stage 'form-removed'"):
        cc.calibrated_check(filtered, z, n_bootstrap=1)
    for bad in (0, 200, 2.5):
        with pytest.raises(ValueError, match="n_bootstrap"):
            cc.calibrated_check(model, z, n_bootstrap=bad)


def test_the_calibrated_check_keeps_the_plain_check_and_its_seed(fitted_case):
    model, z = fitted_case
    first = cc.calibrated_check(model, z, n_simulations=5, n_bootstrap=2, seed=7)
    plain = check_model(model, z, n_simulations=5, seed=7)
    assert first.check.outside == plain.outside
    for a, b in zip(first.check.parameters, plain.parameters):
        np.testing.assert_array_equal(a.simulated, b.simulated)
    assert first.n_bootstrap == 2 and all(v.shape == (2,) for v in first.bootstrap.values())
    assert set(first.outside) <= set(first.p_values)
    again = cc.calibrated_check(model, z, n_simulations=5, n_bootstrap=2, seed=7)
    assert again.p_values == pytest.approx(first.p_values, nan_ok=True)
    record = json.loads(json.dumps(first.to_dict()))
    assert record["calibration"]["n_bootstrap"] == 2
    assert {p["name"] for p in record["parameters"]} == set(first.p_values)


def test_a_copy_whose_refit_cannot_be_checked_is_named(fitted_case, monkeypatch):
    """As on a real AFM crop (data/nid-1-crop.x3p, sm + Johnson): a refit whose simulation is
    refused stops the check with the copy's number and the reason, not a bare library error."""
    model, z = fitted_case

    def refuse(*args, **kwargs):
        raise ValueError("the pre-distorted ACVF is not positive definite on this grid")
    monkeypatch.setattr(cc, "refit_like", refuse)
    with pytest.raises(ValueError, match=r"bootstrap copy 1 of 2: its refitted model cannot be "
                                         r"checked: the pre-distorted ACVF"):
        cc.calibrated_check(model, z, n_simulations=3, n_bootstrap=2)
