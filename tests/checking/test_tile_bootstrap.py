"""The tile bootstrap's predictive models (roughgp.checking.tile_bootstrap): seeded, the
variance and heights of the drawn tiles, the tails modelled, and refusals by name."""

from __future__ import annotations

import dataclasses
import types

import numpy as np
import pytest
import scipy.ndimage

from roughgp.checking.predictive import predictive_models
from roughgp.checking.tile_bootstrap import (
    TILES,
    tile_bootstrap_models,
    tile_bootstrap_refusal,
    tile_heights,
    tile_spread_factor,
)
from roughgp.experiments.held_out import eq18_model
from roughgp.experiments.iaaft_held_out import synthetic_map
from roughgp.surface_models import tile_spectra
from roughgp.surface_models.chain import form_removed
from roughgp.surface_models.fit import fit_psd_model, fit_surface_model
from roughgp.surface_models.measured_psd import band_variance


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
    spread = tile_spread_factor(psd_iaaft, lognormal_map, seed=0)
    rng = np.random.default_rng([0, 5])   # the tiles each model drew, as the bootstrap does
    picks = [rng.integers(0, len(heights), len(heights)) for _ in models]
    factors = np.array([np.var(np.concatenate([heights[k].ravel() for k in p])) / variance
                        for p in picks])
    for m, f in zip(models, factors):   # the band's variance scaled as the tiles' variance
        assert band_variance(m) == pytest.approx(f ** spread * band_variance(psd_iaaft),
                                                 rel=1e-9)
    # a part of two roughnesses: the draws' variance spreads both ways about the fitted one
    assert factors.min() < 0.85 and factors.max() > 1.15
    for m, f in zip(models, factors):
        q = np.asarray(m.marginal["quantiles_um"])
        assert np.all(np.diff(q) >= 0) and m.marginal["tail_probability"] < 1e-6
        body = np.interp([0.25, 0.75], np.linspace(0, 1, q.size), q)
        assert body[1] - body[0] > 0
    spread = [np.ptp(m.marginal["quantiles_um"][400:601]) for m in models]
    assert np.corrcoef(spread, factors)[0, 1] > 0.8   # the rougher draws, the wider heights
    # the drawn heights stretched to the widened variance: at a spread of 2 each model's
    # heights spread sqrt(f) times as wide as at 1 (f ** 2 against f)
    plain = tile_bootstrap_models(psd_iaaft, lognormal_map, 19, seed=0, spread=1.0)
    twice = tile_bootstrap_models(psd_iaaft, lognormal_map, 19, seed=0, spread=2.0)
    for a, b, f in zip(plain, twice, factors):
        qa, qb = np.asarray(a.marginal["quantiles_um"]), np.asarray(b.marginal["quantiles_um"])
        assert np.ptp(qb[400:601]) / np.ptp(qa[400:601]) == pytest.approx(np.sqrt(f), rel=1e-6)
    assert variance > 0


def _log_variance_spreads(model, spread, n_maps=100, shape=(64, 64)):
    """Over ``n_maps`` maps of ``model``: the sd of their log variance (a crop's spread), and
    the mean sd of the log variance of 40 tile-bootstrap models of each, raised to ``spread``."""
    crops, boots = [], []
    for s in range(n_maps):
        z = model.simulate(shape, seed=np.random.default_rng([3, s]))
        crops.append(np.log(np.var(form_removed(z, (1.0, 1.0), model.cutoffs).sl)))
        drawn = tile_bootstrap_models(model, z, 40, seed=s, spread=spread)
        boots.append(np.std(np.log([m.hyperparameters["variance_um2"] for m in drawn])))
    return np.std(crops, ddof=1), np.mean(boots)


def test_a_numpy_number_is_a_spread_like_any_other():
    """``np.int64(2)`` (a factor read from an array) gives the models ``2.0`` gives."""
    long = eq18_model(1.0, 12.0, 12.0, 0.0, 0.0)
    z = np.random.default_rng(3).standard_normal((64, 64))
    assert [m.to_dict() for m in tile_bootstrap_models(long, z, 2, spread=np.int64(2))] \
        == [m.to_dict() for m in tile_bootstrap_models(long, z, 2, spread=2.0)]


def test_the_spread_factor_widens_the_tiles_to_the_crops_spread():
    """Lengths of 3/4 of a tile: the plain bootstrap spreads a crop's log variance about 2/3 as
    wide as independent crops of the model do; raised to the model's own factor, as wide (the
    maps drawn with other seeds than the factor's). White noise: no widening to speak of."""
    long = eq18_model(1.0, 12.0, 12.0, 0.0, 0.0)
    factor = tile_spread_factor(long, np.zeros((64, 64)), seed=0)
    assert factor > 1.3
    crop, plain = _log_variance_spreads(long, 1.0)
    _, widened = _log_variance_spreads(long, factor)
    assert plain < 0.75 * crop and widened == pytest.approx(crop, rel=0.15)
    white = eq18_model(1.0, 0.3, 0.3, 0.0, 0.0)
    assert 1.0 <= tile_spread_factor(white, np.zeros((64, 64)), seed=0) < 1.2
    holes = np.zeros((64, 64))
    holes[20:40, 20:40] = np.nan     # the holes kept in the draws: a factor of its own
    assert tile_spread_factor(long, holes, seed=0) != factor
    assert tile_spread_factor(long, holes, seed=0) == tile_spread_factor(long, holes, seed=0)
    for bad in (0.5, float("nan"), np.inf, True, np.bool_(True), "2"):
        with pytest.raises(ValueError, match="spread must be a finite number >= 1"):
            tile_bootstrap_models(long, np.zeros((64, 64)), 2, spread=bad)
    with pytest.raises(ValueError, match="draws must be an integer >= 2"):
        tile_spread_factor(long, np.zeros((64, 64)), draws=1)


def test_the_spectrum_s_shape_is_the_drawn_tiles_own():
    """A map whose left half has its lay along x and right half along y: the more tiles of
    the left half a model drew, the more of its power lies along the left half's lay."""
    noise = np.random.default_rng(0).standard_normal((128, 128))
    z = np.concatenate([scipy.ndimage.gaussian_filter(noise, (1, 6), mode="wrap")[:, :64],
                        scipy.ndimage.gaussian_filter(noise, (6, 1), mode="wrap")[:, 64:]],
                       axis=1)
    model = fit_psd_model(z, 1.0, marginal="iaaft", s=None, l=None).model
    table = np.asarray(model.hyperparameters["psd_um4"])
    rng = np.random.default_rng([0, 5])
    left, contrast = [], []
    for m in tile_bootstrap_models(model, z, 19, seed=0):
        pick = rng.integers(0, 16, 16)
        factor = np.asarray(m.hyperparameters["psd_um4"]) / table
        left.append(np.mean(pick % 4 < 2))   # columns 0 and 1 of the 4 x 4 tiles
        # long along x: power near qx = 0, the directions 75-105 degrees (bins 15-20)
        contrast.append(np.log(factor[10:30, 15:21].mean()
                               / factor[10:30, np.r_[0:3, 33:36]].mean()))
    assert np.corrcoef(left, contrast)[0, 1] > 0.8
    assert np.ptp(contrast) > 0.5   # a factor of 1.6 between the draws' directional contrast


def test_the_shape_factor_of_every_tile_once_is_one_and_of_too_few_ordinates_one():
    rng = np.random.default_rng(1)
    tiles = [rng.standard_normal((32, 32)) for _ in range(16)]
    sums, counts = tile_spectra.tile_ordinates(tiles, (1.0, 1.0), 1 / 128, 0.75)
    np.testing.assert_allclose(tile_spectra.shape_factor(sums, counts, np.arange(16)), 1.0)
    one = tile_spectra.shape_factor(sums, counts, np.zeros(16, int))  # one tile, 16 times
    thin = (16 * counts[0] < tile_spectra.MIN_ORDINATES)
    rows = np.arange(40) * tile_spectra.RINGS // 40
    cols = np.arange(36) * tile_spectra.ANGLES // 36
    assert thin.any() and np.all(one[thin[np.ix_(rows, cols)]] == 1.0)  # below the tiles' reach
    assert not np.allclose(one[~thin[np.ix_(rows, cols)]], 1.0)
    tiles[3] = np.full((32, 32), np.nan)                 # a tile with no measured point
    tiles[5][:, 1:-1] = np.nan                           # measured only where the window is 0
    sums, counts = tile_spectra.tile_ordinates(tiles, (1.0, 1.0), 1 / 128, 0.75)
    assert counts[3].sum() == counts[5].sum() == 0 and counts[4].sum() > 0
    assert np.all(tile_spectra.shape_factor(sums, counts, [3] * 16) == 1.0)
    with pytest.raises(ValueError, match="0 < f_min < f_max"):
        tile_spectra.tile_ordinates(tiles, (1.0, 1.0), 0.5, 0.25)


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
