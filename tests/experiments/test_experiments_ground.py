"""roughgp.experiments.ground: figure 2's surface, its ACVF against eq 18, its texture (small
sizes; the chapter "Ground surfaces" and the ledger run the paper's)."""

import dataclasses
import math

import numpy as np
import pytest

from roughgp.experiments import ground
from roughgp.models import surfaces

SMALL = surfaces.GrooveParameters(variance=10.0, lengthscales=(15.0, 2.0), angle=math.pi / 6)
SHAPE = (96, 128)


def small_surface(seed=5):
    return ground.figure2_surface(seed, parameters=SMALL, shape=SHAPE, noise_variance=1.0)


def test_the_surface_is_an_exact_draw_equal_to_surfaces_ground():
    result = small_surface()
    z = surfaces.ground(SHAPE, **dataclasses.asdict(SMALL), noise_variance=1.0, seed=5)
    latent = surfaces.ground(SHAPE, **dataclasses.asdict(SMALL), seed=5, latent=True)
    np.testing.assert_array_equal(result.surface, z)
    np.testing.assert_array_equal(result.latent, latent)
    assert result.shape == SHAPE and result.clipped_fraction == 0.0
    assert result.min_eigenvalue >= -1e-10
    assert abs(result.residual_variance - 1.0) < 5 * math.sqrt(2 / z.size)
    assert small_surface() is result                     # cached
    assert not result.surface.flags.writeable            # the cache cannot be altered
    assert not np.array_equal(small_surface(6).surface, z)


def test_the_seed_must_be_an_integer():
    with pytest.raises(ValueError, match="seed must be an integer"):
        ground.figure2_surface(None, parameters=SMALL, shape=SHAPE)


def test_acvf_deviation_is_small_for_an_exact_draw_and_large_for_a_wrong_model():
    result = small_surface()
    acvf = ground.figure2_acvf_deviation(result, max_lag=40, reach=(80.0, 12.0))
    assert acvf.spread > 0 and 0 < acvf.mean_variance < SMALL.variance
    for line in (acvf.along, acvf.across):
        assert np.all(np.diff(line.distance) >= 0) and line.distance[0] == 0
        assert line.estimate.shape == line.model.shape == line.distance.shape
        assert line.model[0] == pytest.approx(SMALL.variance)
    assert acvf.largest == max(acvf.along.deviation, acvf.across.deviation) <= 4
    # the same latent judged against eq 18 with the lengthscales swapped fails
    wrong = dataclasses.replace(result, parameters=dataclasses.replace(SMALL, angle=SMALL.angle
                                                                       + math.pi / 2))
    assert ground.figure2_acvf_deviation(wrong, max_lag=40, reach=(80.0, 12.0)).largest > 4


def test_texture_reads_the_model():
    result = small_surface()
    tex = ground.figure2_texture(result, n_repeats=2)
    assert tex.seeds == (5, 6, 7)
    assert tex.std.shape == tex.sq.shape == tex.sal.shape == tex.str.shape == (3,)
    assert tex.predicted_sal == pytest.approx(2.0 * math.log(5 * 10 / 11))
    assert tex.predicted_str == pytest.approx(2.0 / 15.0)
    assert tex.expected_sq < math.sqrt(11.0)
    assert np.all(np.abs(tex.sq - tex.expected_sq) <= 4 * tex.sq_spread)
    # Std scatters by about 2 deg from draw to draw around about 31.5 deg on this small grid
    # (16 seeds: sd 1.8 and 2.3 deg, before and after the embedding's truncation)
    assert np.all(np.abs(tex.std - 30.0) <= 7.0) and abs(np.mean(tex.std) - 30.0) <= 4.0
    assert tex.angles.shape == tex.power.shape
