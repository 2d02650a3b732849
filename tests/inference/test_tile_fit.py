"""Eq 18 fitted per tile with the sandwich covariance (roughgp.inference.tile_fit and
whittle_fit.robust_covariance, issue 40 item 4)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from roughgp.inference.tile_fit import fit_tiles
from roughgp.inference.whittle_fit import fit_whittle, robust_covariance
from roughgp.models.surfaces import ground


def test_the_sandwich_errors_hold_the_spread_the_information_understates():
    """16 maps of 48 x 48 points of one eq 18 model: the estimates' spread over the maps
    against each kind of standard error. The inverse information understates it (its z
    scores spread over 1.4); the sandwich's z scores have a spread near 1."""
    truth = np.log([2.0, 6.0, 2.0])
    z_info, z_sandwich = [], []
    for seed in range(16):
        z = ground((48, 48), variance=2.0, lengthscales=(6.0, 2.0), angle=0.5,
                   noise_variance=0.05, seed=seed)
        fit = fit_whittle(z)
        sandwich = robust_covariance(fit, np.isfinite(z), n_draws=30, seed=seed)
        error = np.asarray(fit.u[:3]) - truth
        z_info.append(error / fit.standard_errors()[:3])
        z_sandwich.append(error / np.sqrt(np.diag(sandwich))[:3])
    assert np.std(z_info) > 1.4
    assert 0.7 < np.std(z_sandwich) < 1.3


def test_tiles_are_fitted_each_on_its_own_points():
    """A map whose right half is three times rougher: the right tiles' variance is about three
    times the left ones'; centres at the tiles' middles; a tile of holes has no estimate."""
    z = ground((64, 96), variance=1.0, lengthscales=(5.0, 2.0), angle=0.3,
               noise_variance=0.02, seed=4)
    z[:, 48:] *= math.sqrt(3.0)
    z[:32, :48] = np.nan
    fits = fit_tiles(z, 1.0, tiles=(2, 2), n_draws=10, seed=0)
    assert fits.centres_x.tolist() == [23.5, 71.5] and fits.centres_y.tolist() == [15.5, 47.5]
    assert np.isnan(fits.estimates[0, 0]).all() and fits.n_points[0, 0] == 0
    ratio = math.exp(fits.estimates[1, 1, 0] - fits.estimates[1, 0, 0])
    assert 1.8 < ratio < 5.0
    assert np.isfinite(fits.pooling_variances()[1]).all()
    again = fit_tiles(z, 1.0, tiles=(2, 2), n_draws=10, seed=0)
    np.testing.assert_array_equal(np.nan_to_num(again.covariances), np.nan_to_num(fits.covariances))


@pytest.mark.parametrize("kwargs, words", [
    (dict(tiles=(8, 1)), "tiles must be (m, n)"),
    (dict(n_draws=3), "n_draws"),
])
def test_bad_tiles_are_refused(kwargs, words):
    z = np.random.default_rng(0).standard_normal((64, 64))
    with pytest.raises(ValueError) as error:
        fit_tiles(z, 1.0, **kwargs)
    assert words in str(error.value)
