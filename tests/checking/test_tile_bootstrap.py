"""The tile bootstrap's predictive models (roughgp.checking.tile_bootstrap): seeded, the
variance and heights of the drawn tiles, the tails modelled, and refusals by name."""

from __future__ import annotations

import dataclasses
import types

import numpy as np
import pytest

from roughgp.checking.predictive import predictive_models
from roughgp.checking.tile_bootstrap import (
    TILES,
    tile_bootstrap_models,
    tile_bootstrap_refusal,
    tile_heights,
)
from roughgp.experiments.iaaft_held_out import synthetic_map
from roughgp.surface_models.fit import fit_psd_model, fit_surface_model


@pytest.fixture(scope="module")
def lognormal_map():
    """64 x 64 points of the lognormal kind, its right half twice as rough."""
    z = synthetic_map("lognormal", 1, shape=(64, 128))[:, :64].copy()
    z[:, 32:] = 2.0 * (z[:, 32:] - z.mean()) + z.mean()
    return z


@pytest.fixture(scope="module")
def psd_iaaft(lognormal_map):
    return fit_psd_model(lognormal_map, 1.0, marginal="iaaft", s=None, l=None).model


def test_the_same_seed_gives_the_same_models(lognormal_map, psd_iaaft):
    a = tile_bootstrap_models(psd_iaaft, lognormal_map, 3, seed=4)
    b = tile_bootstrap_models(psd_iaaft, lognormal_map, 3, seed=4)
    c = tile_bootstrap_models(psd_iaaft, lognormal_map, 3, seed=5)
    assert [m.marginal for m in a] == [m.marginal for m in b]
    assert [m.hyperparameters for m in a] == [m.hyperparameters for m in b]
    assert [m.hyperparameters for m in a] != [m.hyperparameters for m in c]


def test_each_model_has_the_variance_and_heights_of_its_tiles(lognormal_map, psd_iaaft):
    heights, filtered = tile_heights(lognormal_map, None, psd_iaaft)
    assert len(heights) == TILES[0] * TILES[1] and all(h.shape == (16, 16) for h in heights)
    variance = np.var(np.concatenate([h.ravel() for h in heights]))
    models = tile_bootstrap_models(psd_iaaft, lognormal_map, 19, seed=0)
    ratios = [np.asarray(m.hyperparameters["psd_um4"]) / np.asarray(
        psd_iaaft.hyperparameters["psd_um4"]) for m in models]
    for r in ratios:   # one factor over the whole table
        np.testing.assert_allclose(r, r.flat[0])
    factors = np.array([r.flat[0] for r in ratios])
    # a part of two roughnesses: the draws' variance spreads both ways about the fitted one
    assert factors.min() < 0.85 and factors.max() > 1.15
    for m, f in zip(models, factors):
        q = np.asarray(m.marginal["quantiles_um"])
        assert np.all(np.diff(q) >= 0) and m.marginal["tail_probability"] < 1e-6
        body = np.interp([0.25, 0.75], np.linspace(0, 1, q.size), q)
        assert body[1] - body[0] > 0
    spread = [np.ptp(m.marginal["quantiles_um"][400:601]) for m in models]
    assert np.corrcoef(spread, factors)[0, 1] > 0.8   # the rougher draws, the wider heights
    assert variance > 0


def test_eq18_scales_its_variance_and_noise_alike(lognormal_map):
    model = fit_surface_model(np.log(lognormal_map), 1.0, block=12, n_blocks=4, s=None,
                              l=None).model
    for m in tile_bootstrap_models(model, np.log(lognormal_map), 4, seed=1):
        ratio = m.hyperparameters["variance_um2"] / model.hyperparameters["variance_um2"]
        assert m.hyperparameters["noise_variance_um2"] == pytest.approx(
            ratio * model.hyperparameters["noise_variance_um2"])
        assert m.hyperparameters["lambda_a_um"] == model.hyperparameters["lambda_a_um"]
        assert m.marginal is None


def test_predictive_models_draws_the_tiles_of_the_fitted_map(lognormal_map, psd_iaaft):
    models, held = predictive_models(psd_iaaft, 2, source="tiles", seed=3,
                                     fitted=(lognormal_map, (1.0, 1.0)))
    assert held == () and len(models) == 2
    assert [m.marginal for m in models] == [
        m.marginal for m in tile_bootstrap_models(psd_iaaft, lognormal_map, 2, seed=3)]
    with pytest.raises(ValueError, match="needs the map the model was fitted on"):
        predictive_models(psd_iaaft, 2, source="tiles")


def test_refusals_name_what_is_wrong(lognormal_map, psd_iaaft):
    with pytest.raises(ValueError, match="tiles: 4 x 4 tiles of a 32 x 64 map are shorter"):
        tile_bootstrap_models(psd_iaaft, lognormal_map[:32], 2)
    with pytest.raises(ValueError, match=r"n_models must be an integer >= 1 and <= 99"):
        tile_bootstrap_models(psd_iaaft, lognormal_map, 0)
    assert "this is a sm2d model" in tile_bootstrap_refusal(
        types.SimpleNamespace(equation="sm2d", stage="form-removed"))
    with pytest.raises(ValueError, match="of stage 'filtered'"):
        tile_bootstrap_models(dataclasses.replace(psd_iaaft, stage="filtered"), lognormal_map, 2)
