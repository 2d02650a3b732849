"""The IAAFT table keyed at the model's own order statistics
(roughgp.surface_models.order_scores): a correlated surface's extremes and spread come back."""

from __future__ import annotations

import dataclasses
import json

import numpy as np
import pytest

from roughgp.checking.model_check import check_model
from roughgp.experiments.held_out import eq18_model
from roughgp.surface_models import iaaft
from roughgp.surface_models.chain import form_removed, marginal_of
from roughgp.surface_models.fit import fit_psd_model
from roughgp.surface_models.order_scores import (
    draws_for,
    order_scores,
    scores_for_table,
    with_order_scores,
)
from model_file_refusal import assert_refused

#: eq 18 of lengths 12 and 4 points: a 96 x 96 map holds few correlation areas
TRUE = eq18_model(1.0, 12.0, 4.0, 30.0, 0.0)
SHAPE = (96, 96)


def _plug_in(z):
    """The true covariance with the map's own IAAFT heights (after the F-operator, as a fit
    keeps them), keyed at its order scores."""
    heights = form_removed(z, (1.0, 1.0), TRUE.cutoffs).sl
    model = dataclasses.replace(TRUE, marginal=marginal_of(heights, "iaaft"))
    return with_order_scores(model, z, (1.0, 1.0))


def _mean_ranks(keyed, n_maps=8):
    """The measured Sz and Sq's mean rank among 19 simulations of the measured-PSD model with
    IAAFT heights fitted to each of ``n_maps`` maps of :data:`TRUE`, its table keyed at the
    order scores or (``keyed=False``) at the Hazen positions."""
    ranks = {"Sz": [], "Sq": []}
    for i in range(n_maps):
        z = TRUE.simulate(SHAPE, seed=100 + i)
        model = fit_psd_model(z, 1.0, marginal="iaaft").model
        if not keyed:
            model = dataclasses.replace(model, marginal={
                k: v for k, v in model.marginal.items() if k != "order_scores"})
        check = check_model(model, z, (1.0, 1.0), n_simulations=19, seed=i)
        for p in check.parameters:
            if p.name in ranks:
                ranks[p.name].append(p.rank)
    return {name: float(np.mean(r)) for name, r in ranks.items()}


def test_the_keys_are_a_correlated_surfaces_order_statistics():
    z = TRUE.simulate(SHAPE, seed=1)
    model = _plug_in(z)
    keys = np.asarray(model.marginal["order_scores"])
    hazen = iaaft.hazen_scores(model.marginal["tail_probability"], keys.size)
    assert np.all(np.diff(keys) > 0) and keys[0] == pytest.approx(-keys[-1])
    # the highest of 9216 correlated points lies well inside the Hazen position of the
    # highest of 9216 independent ones (3.87); the middle of the table hardly moves
    assert 3.0 < keys[-1] < hazen[-1] - 0.2
    middle = slice(keys.size // 4, 3 * keys.size // 4)
    np.testing.assert_allclose(keys[middle], hazen[middle], atol=0.1)
    # the same seed gives the same keys; another seed keys within the draws' noise
    assert order_scores(model, z, (1.0, 1.0)) == model.marginal["order_scores"]
    other = np.asarray(order_scores(model, z, (1.0, 1.0), seed=1))
    assert np.max(np.abs(other - keys)) < 0.15


def test_the_measured_extremes_rank_among_the_simulations_as_a_true_models_do():
    """With the keys, the IAAFT simulations of the measured-PSD model put the measured Sz and
    Sq in the middle of theirs (mean rank 9.5 of 0-19 for a model that describes the map);
    keyed at the Hazen positions, the measured surfaces were rougher than the simulations. Run
    before the thresholds were set (8 maps): keyed Sz 9.9, Sq 9.8; Hazen Sz 16.6, Sq 14.0."""
    keyed, hazen = _mean_ranks(True), _mean_ranks(False)
    assert abs(keyed["Sz"] - 9.5) < 2.5 and abs(keyed["Sq"] - 9.5) < 2.5
    assert hazen["Sz"] > keyed["Sz"] + 3.0 and hazen["Sq"] > keyed["Sq"] + 2.0


def test_a_tile_bootstraps_table_is_keyed_at_the_same_scores():
    z = TRUE.simulate(SHAPE, seed=2)
    marginal = _plug_in(z).marginal
    n = len(marginal["quantiles_um"])
    same = scores_for_table(marginal, marginal["tail_probability"], n)
    np.testing.assert_allclose(same, marginal["order_scores"], atol=1e-12)
    wider = np.asarray(scores_for_table(marginal, 1e-6, n))   # a table reaching further out
    assert wider[0] < marginal["order_scores"][0] and np.all(np.diff(wider) > 0)
    assert scores_for_table({**marginal, "order_scores": None}, 1e-6, n) is None


@pytest.mark.parametrize("spoil, words", [
    (lambda keys: keys[::-1], "strictly increasing"),
    (lambda keys: keys[:-1], "must hold"),
    (lambda keys: keys[:5] + [float("nan")] + keys[6:], "order_scores[5]"),
    (lambda keys: [k * 100 for k in keys], "order_scores[0]"),
])
def test_model_files_with_bad_order_scores_are_refused(spoil, words):
    record = _plug_in(TRUE.simulate((32, 32), seed=3)).to_dict()

    def spoilt(r):
        r["marginal"]["order_scores"] = spoil(list(r["marginal"]["order_scores"]))
    assert_refused(record, spoilt, words)


def test_a_model_file_keeps_its_keys_and_draws_the_same():
    model = _plug_in(TRUE.simulate((32, 32), seed=4))
    again = type(model).from_dict(json.loads(json.dumps(model.to_dict())))
    assert again.marginal["order_scores"] == model.marginal["order_scores"]
    np.testing.assert_array_equal(again.simulate((32, 32), seed=5), model.simulate((32, 32),
                                                                                   seed=5))


def test_larger_maps_average_fewer_draws_drawn_a_chunk_at_a_time():
    assert draws_for(64 * 64) == draws_for(256 * 256) == 32
    assert draws_for(512 * 512) == 8 == draws_for(4096 * 4096)
    assert draws_for(300 * 300) == 24   # 24 draws of 90 000 points: two chunks (23 and 1)
    z = TRUE.simulate((300, 300), seed=6)
    keys = np.asarray(_plug_in(z).marginal["order_scores"])
    assert np.all(np.diff(keys) > 0) and keys[-1] == pytest.approx(-keys[0])


@pytest.mark.parametrize("kwargs, words", [
    ({"seed": -1}, "seed must be an integer >= 0"),
    ({"seed": 1.5}, "seed must be an integer"),
    ({"n_draws": 1}, "n_draws must be an integer >= 2 and <= 1000"),
    ({"n_draws": 10 ** 6}, "n_draws must be an integer >= 2 and <= 1000"),
])
def test_bad_arguments_are_refused_by_name(kwargs, words):
    z = TRUE.simulate((16, 16), seed=7)
    model = _plug_in(z)
    with pytest.raises(ValueError, match=words):
        order_scores(model, z, (1.0, 1.0), **kwargs)


def test_a_model_without_iaaft_heights_has_no_order_scores():
    z = TRUE.simulate((16, 16), seed=8)
    assert with_order_scores(TRUE, z, (1.0, 1.0)) is TRUE
    with pytest.raises(ValueError, match="key an IAAFT marginal"):
        order_scores(TRUE, z, (1.0, 1.0))
