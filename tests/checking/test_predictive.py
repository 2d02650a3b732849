"""The predictive simulations (roughgp.checking.predictive, issue 40): bootstrap refits that
carry the fit's uncertainty, their centring, seeds and refusals."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from roughgp.checking.model_check import draw_models
from roughgp.checking.predictive import (
    MAX_MODELS,
    bootstrap_models,
    fitted_shape,
    recentred,
)
from roughgp.experiments.held_out import synthetic_map
from roughgp.surface_models.fit import fit_surface_model


@pytest.fixture(scope="module")
def fitted():
    z, _, _ = synthetic_map("stationary", 0, shape=(32, 32))
    return fit_surface_model(z, 1.0, block=12, n_blocks=4, seed=1).model


def _with(model, **values):
    return dataclasses.replace(model, hyperparameters={**model.hyperparameters, **values})


def test_the_refits_are_recentred_in_logs_with_their_spread_kept(fitted):
    v = fitted.hyperparameters["variance_um2"]
    refits = [_with(fitted, variance_um2=v * f) for f in (0.5, 0.8)]  # geometric mean 0.632 v
    mean = np.exp(np.mean(np.log([0.5 * v, 0.8 * v])))
    for centre, target in (("refits", mean), ("fit", v), ("bias-corrected", v * v / mean)):
        moved = [r.hyperparameters["variance_um2"] for r in recentred(fitted, refits, centre)]
        assert np.exp(np.mean(np.log(moved))) == pytest.approx(target, rel=1e-12)
        assert moved[1] / moved[0] == pytest.approx(1.6, rel=1e-12)
    assert recentred(fitted, refits[:1], "fit") == tuple(refits[:1])  # one refit: no mean
    with pytest.raises(ValueError, match="centre must be one of refits, fit, bias-corrected"):
        recentred(fitted, refits, "median")


def test_the_same_seed_gives_the_same_refits(fitted):
    assert fitted_shape(fitted, None) == (32, 32)
    calls = []
    first = bootstrap_models(fitted, 2, seed=3, progress=lambda b, n: calls.append((b, n)))
    again = bootstrap_models(fitted, 2, seed=3)
    other = bootstrap_models(fitted, 2, seed=4)
    assert calls == [(1, 2), (2, 2)]
    assert [m.hyperparameters for m in first] == [m.hyperparameters for m in again]
    assert [m.hyperparameters for m in first] != [m.hyperparameters for m in other]
    assert first[0].hyperparameters != first[1].hyperparameters


@pytest.mark.parametrize("options, words", [
    (dict(n_models=0), f"n_models must be an integer in [1, {MAX_MODELS}]"),
    (dict(n_models=MAX_MODELS + 1), f"n_models must be an integer in [1, {MAX_MODELS}]"),
    (dict(n_models=2, seed=-1), "seed must be an integer >= 0"),
    (dict(n_models=2, centre="mode"), "centre must be one of"),
])
def test_bad_bootstrap_arguments_are_refused(fitted, options, words):
    with pytest.raises(ValueError) as error:
        bootstrap_models(fitted, **options)
    assert words in str(error.value)


def test_a_model_without_a_fitted_shape_or_a_form_removed_stage_is_refused(fitted):
    with pytest.raises(ValueError, match="no fitted shape"):
        bootstrap_models(dataclasses.replace(fitted, data={}), 2)
    with pytest.raises(ValueError, match="form-removed"):
        bootstrap_models(dataclasses.replace(fitted, stage="filtered"), 2)


def test_the_draws_take_the_models_in_turn(fitted):
    a, b = _with(fitted, variance_um2=1.0), _with(fitted, variance_um2=2.0)
    assert draw_models(fitted, None, 3) == [fitted] * 3
    assert draw_models(fitted, (a, b), 5) == [a, b, a, b, a]
    with pytest.raises(ValueError, match="non-empty sequence"):
        draw_models(fitted, (), 3)
