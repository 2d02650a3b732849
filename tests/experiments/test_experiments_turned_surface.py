"""Tests of roughgp.experiments.turned_surface (figures 6, 7: eq 22 fitted and its flaw), at a
small size: a 16 x 1536 surface (six feeds), Q = 2 per direction."""

import numpy as np
import pytest

from roughgp.experiments import turned_surface as ts

SHAPE, Q, SEED = (16, 1536), 2, 3


@pytest.fixture(scope="module")
def result():
    return ts.turned_surface_flaw(shape=SHAPE, q=Q, seed=SEED, n_sim=3)


def test_fits_describe_the_surface_and_are_cached(result):
    fits = result.fits
    assert fits.z.shape == SHAPE and fits.x.size == SHAPE[1] and fits.y.size == SHAPE[0]
    np.testing.assert_allclose(fits.across_feed, fits.z.mean(axis=0))
    residual = fits.z - fits.across_feed[None, :] - fits.along_lay[:, None] + fits.z.mean()
    assert fits.noise_variance == pytest.approx(residual.var())
    assert fits.feed == ts.PARAMS.feed and fits.careful_x is None
    assert ts.fit_turned_surface(SHAPE, q=Q, seed=SEED) is fits        # one fit, shared
    with pytest.raises(ValueError, match="careful=True"):
        fits.careful_gain


def test_flaw_measures_have_their_shapes_and_the_data_is_periodic(result):
    assert result.data.periodicity.shape == (1, ts.N_PERIODS)
    assert result.paper.periodicity.shape == (3, ts.N_PERIODS)
    assert result.paper.short_share.shape == (3,) and result.paper.examples.shape == (3, *SHAPE)
    assert np.all(result.data_periodicity > 0.9)                      # the feed marks repeat
    assert 0 < result.data_short_share < 1 and np.all((result.paper.short_share > 0)
                                                      & (result.paper.short_share < 1))
    assert result.paper.cutoff == ts.PARAMS.feed / 8
    # the flaw, even at this size: the simulations lose periodicity over five feeds
    assert result.paper.mean_periodicity[-1] < result.data_periodicity[-1] - 0.1


def test_simulations_are_seeded_and_add_the_fitted_noise(result):
    fits = result.fits
    a = ts.simulate_additive(fits, fits.fit_x, 2, seed=5)
    b = ts.simulate_additive(fits, fits.fit_x, 2, seed=5)
    c = ts.simulate_additive(fits, fits.fit_x, 2, seed=6)
    assert a.shape == (2, *SHAPE)
    np.testing.assert_array_equal(a, b)
    assert not np.allclose(a, c)
    # the first differences of a row see the white noise twice over, at least
    assert np.diff(a, axis=-1).var() > 2 * fits.noise_variance * 0.9
