"""The fill's band by hole size and depth (roughgp.filling.hole_band): depths and hole classes
as defined, factors near the Gaussian 1.96 where the model is the truth, wider deep in large
holes where the model is too confident there, honest widening where the map cannot hold out
discs as large as its holes, and the same seed giving the same band."""

import math

import numpy as np
import pytest

from roughgp.filling import hole_band as hb
from roughgp.gp.kernels import RotatedExponentialKernel
from roughgp.models import surfaces


def _disc(shape, centre, width):
    iy, ix = np.indices(shape)
    off = 0.5 * (width % 2 == 0)
    return (iy - centre[0] + off) ** 2 + (ix - centre[1] + off) ** 2 <= (width / 2) ** 2


@pytest.mark.parametrize("width", [1, 2, 5, 12, 31])
def test_a_hole_of_width_w_is_about_w_over_two_deep(width):
    missing = _disc((80, 80), (40, 40), width)
    labels, deepest = hb.hole_class(missing)
    assert labels.max() == 1
    assert abs(2 * deepest[0] - width) <= 1.5
    assert hb.hole_depth(missing)[~missing].max() == 0


def test_depth_classes_follow_the_edges():
    assert list(hb.depth_class([0.0, 1.0, 1.9, 2.0, 3.99, 4.0, 20.0, 100.0])) == \
        [-1, 0, 0, 1, 1, 2, 4, 6]


def _map(seed, n=96, lengths=(6.0, 6.0)):
    z = surfaces.ground((n, n), variance=1.0, lengthscales=lengths, angle=0.0, noise_variance=1e-4,
                        seed=seed)
    rng = np.random.default_rng(seed)
    missing = np.zeros(z.shape, dtype=bool)
    for width in list(rng.integers(2, 6, 20)) + list(rng.integers(11, 21, 4)):
        missing |= _disc(z.shape, rng.integers(0, n, 2), int(width))
    return z, missing


def test_the_true_model_gets_gaussian_factors_and_the_same_seed_the_same_band():
    z, missing = _map(1, n=128)
    kernel = RotatedExponentialKernel(1.0, (6.0, 6.0))
    residual = np.where(missing, np.nan, z)
    band = hb.calibrate_hole_band(residual, kernel, noise_variance=1e-4, spacing=1.0, seed=0)
    assert set(band.calibrated_classes) >= set(band.hole_classes)
    factors = [f for row in band.factors for f in row if np.isfinite(f)]
    assert 1.5 < min(factors) and max(factors) < 2.6, band.factors
    assert band.calibrated_width >= 2 * 8.5           # the 11-20 holes are held out
    again = hb.calibrate_hole_band(residual, kernel, noise_variance=1e-4, spacing=1.0, seed=0)
    np.testing.assert_array_equal(again.factors, band.factors)
    assert again.held_out == band.held_out


def test_an_overconfident_model_gets_wider_factors_that_hold_95_percent_of_the_holes():
    # the surface has 3-point lengths, the model 12: too confident in every hole; the
    # Gaussian band misses many true heights, the calibrated one holds about 95 % of them
    from roughgp.filling.local_fill import fill_gaps_locally
    from roughgp.filling.self_check import predictive_sd
    z, missing = _map(2, n=128, lengths=(3.0, 3.0))
    kernel = RotatedExponentialKernel(1.0, (12.0, 12.0))
    residual = np.where(missing, np.nan, z)
    band = hb.calibrate_hole_band(residual, kernel, noise_variance=1e-4, spacing=1.0, seed=0)
    assert min(f for row in band.factors for f in row if np.isfinite(f)) > 3.0, band.factors
    fill = fill_gaps_locally(residual, kernel, noise_variance=1e-4, tile=16, margin=6)
    error = np.abs(fill.mean - z)[missing]
    s = predictive_sd(fill.sd, 1e-4)[missing]
    assert np.mean(error <= 1.96 * s) < 0.8
    assert 0.92 <= np.mean(error <= band.factor_map(missing)[missing] * s) <= 0.98


def test_holes_larger_than_the_map_can_hold_out_get_the_widened_factor():
    z, missing = _map(3, n=64)
    missing |= _disc(z.shape, (32, 32), 30)      # 15 deep: over a sixth of 64 points
    kernel = RotatedExponentialKernel(1.0, (6.0, 6.0))
    band = hb.calibrate_hole_band(np.where(missing, np.nan, z), kernel, noise_variance=1e-4,
                                  spacing=1.0, seed=0)
    assert band.uncalibrated_classes and band.calibrated_width < 30
    factor = band.factor_map(missing)
    big = _disc(z.shape, (32, 32), 30) & (hb.hole_depth(missing) > 2)
    # the untested factor, times the local roughness, never below the far-from-data one
    np.testing.assert_allclose(factor[big], np.maximum(band.widened_factor * band.scale[big],
                                                       band.marginal))
    assert np.all(np.abs(np.log(band.scale[big])) < np.log(1.5))   # a stationary map
    assert band.widened_factor >= band.marginal > 1.0
    assert "untested, widened factor" in band.summary()
    assert np.all(factor[~missing] == 0) and np.all(factor[missing] > 0)


def test_the_fill_writes_the_band_of_the_depth_classes():
    from roughgp.filling.measured import fill_measured_surface
    z, missing = _map(4)
    result = fill_measured_surface(np.where(missing, np.nan, z), seed=0, self_check=True,
                                   block=16, n_blocks=6)
    assert result.hole_band is not None
    np.testing.assert_allclose(result.band, result.hole_band.factor_map(missing)
                               * result.predictive_sd)
    assert len(np.unique(np.round(result.band_factors[missing], 9))) > 1
    plain = fill_measured_surface(np.where(missing, np.nan, z), seed=0, block=16, n_blocks=6)
    assert plain.hole_band is None
    assert math.isclose(plain.band_factors[missing][0], 1.959963984540054)


def test_a_rough_zone_widens_the_band_there_and_not_elsewhere():
    """A map whose right quarter is 4 times as rough (the flank of a land, a worn zone): the
    fitted stationary model is too confident there and too cautious elsewhere. Scaled by the
    local roughness (roughgp.filling.local_scale) the band holds about 95 % in both zones;
    the factors by hole size alone miss most of the rough zone's heights."""
    from roughgp.filling.local_fill import fill_gaps_locally
    from roughgp.filling.local_scale import local_scale
    from roughgp.filling.self_check import predictive_sd
    n = 128
    z, missing = _map(5, n=n)
    z[:, 3 * n // 4:] *= 4.0
    rough = np.zeros(z.shape, dtype=bool)
    rough[:, 3 * n // 4 + 4:] = True
    residual = np.where(missing, np.nan, z)
    scale = local_scale(residual, missing)
    assert np.median(scale[missing & rough]) > 2 * np.median(scale[missing & ~rough])
    kernel = RotatedExponentialKernel(float(np.var(z)), (6.0, 6.0))
    band = hb.calibrate_hole_band(residual, kernel, noise_variance=1e-4, spacing=1.0, seed=0)
    fill = fill_gaps_locally(residual, kernel, noise_variance=1e-4, tile=16, margin=6)
    error = np.abs(fill.mean - z)
    s = predictive_sd(fill.sd, 1e-4)
    factor = band.factor_map(missing)
    unscaled = hb.HoleBand(*[getattr(band, f) for f in (
        "factors", "copies", "held_out", "rounds", "marginal", "hole_classes", "deepest_hole",
        "deepest_copy", "seconds")]).factor_map(missing)
    for zone in (missing & rough, missing & ~rough):
        assert 0.88 <= np.mean(error[zone] <= factor[zone] * s[zone]) <= 0.995
    assert np.mean(error[missing & rough] <= unscaled[missing & rough] * s[missing & rough]) \
        < 0.85


def test_local_scale_refuses_a_missing_map_of_another_shape():
    from roughgp.filling.local_scale import local_scale
    with pytest.raises(ValueError, match="missing must have the shape"):
        local_scale(np.zeros((8, 8)), np.zeros((8, 9), dtype=bool))
