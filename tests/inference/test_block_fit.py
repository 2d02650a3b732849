"""Tests of roughgp.inference.block_fit: eq 18 plus noise fitted to the measured points of a map with
holes by maximum block composite likelihood."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from roughgp.inference.block_fit import BlockLikelihood, fit_ground_to_valid_points
from roughgp.models import surfaces

TRUTH = surfaces.GrooveParameters(variance=4.0, lengthscales=(12.0, 3.0), angle=-0.6)
NOISE = 0.1


def _measured(seed=0, shape=(128, 128), dropout=0.1):
    z = surfaces.ground(shape, **dataclasses.asdict(TRUTH), noise_variance=NOISE, seed=seed)
    z[np.random.default_rng(seed + 100).random(shape) < dropout] = np.nan
    return z


@pytest.fixture(scope="module")
def fit():
    return fit_ground_to_valid_points(_measured(), seed=0, block=16, n_blocks=12)


def test_recovers_the_hyperparameters(fit):
    # six surfaces (seeds 0-5) gave variance 3.4-4.7, lambda_a 11.0-13.8, lambda_b 2.5-3.3,
    # angle -0.603..-0.585 and noise 0.05-0.18: the bounds are about twice that spread
    g = fit.groove
    assert abs(g.variance / TRUTH.variance - 1) < 0.35
    assert abs(g.lengthscales[0] / TRUTH.lengthscales[0] - 1) < 0.3
    assert abs(g.lengthscales[1] / TRUTH.lengthscales[1] - 1) < 0.3
    assert abs(g.angle - TRUTH.angle) < 0.06
    assert NOISE / 3 < fit.noise_variance < 3 * NOISE


def test_reports_ordered_lengthscales_and_a_wrapped_angle(fit):
    assert fit.groove.lengthscales[0] >= fit.groove.lengthscales[1]
    assert -math.pi / 2 <= fit.groove.angle < math.pi / 2
    assert fit.kernel.hyperparameters()["angle"].item() == pytest.approx(fit.groove.angle)


def test_uses_qualifying_blocks_only(fit):
    z = _measured()
    assert len(fit.blocks) == 12 and len(set(fit.blocks)) == 12
    counted = 0
    for r, c in fit.blocks:
        window = ~np.isnan(z[r:r + 16, c:c + 16])
        assert window.shape == (16, 16) and window.mean() >= 0.5
        counted += window.sum()
    assert fit.n_points == counted
    assert fit.mean == pytest.approx(np.nanmean(z))


def test_the_same_seed_gives_the_same_fit():
    z = _measured(seed=3, shape=(48, 48))
    a = fit_ground_to_valid_points(z, seed=1, block=12, n_blocks=3, maxiter=200)
    b = fit_ground_to_valid_points(z, seed=1, block=12, n_blocks=3, maxiter=200)
    assert a == b


def test_mask_removes_points_from_the_fit():
    z = _measured(seed=3, shape=(48, 48), dropout=0.0)
    mask = np.zeros(z.shape, dtype=bool)
    mask[:, :24] = True  # the left half is distrusted: only right-half blocks qualify
    fit = fit_ground_to_valid_points(z, mask=mask, seed=1, block=12, n_blocks=8, maxiter=100)
    assert all(c >= 24 for _, c in fit.blocks)
    assert len(fit.blocks) == 8


@pytest.mark.parametrize("kwargs, message", [
    ({"block": 3}, r"block must be an integer >= 4"),
    ({"block": 49}, r"block must be in \[4, 48\]"),
    ({"n_blocks": 0}, r"n_blocks must be an integer >= 1"),
    ({"min_valid": 0.0}, r"min_valid must be in \(0, 1\]"),
    ({"mask": np.zeros((4, 4), dtype=bool)}, r"mask must be a boolean array of the shape"),
])
def test_rejects_bad_arguments(kwargs, message):
    with pytest.raises(ValueError, match=message):
        fit_ground_to_valid_points(_measured(shape=(48, 48)), **kwargs)


def test_rejects_maps_without_usable_blocks():
    z = _measured(shape=(48, 48))
    z[::2, :] = np.nan  # half of every block missing, and then some
    z[1::4, :] = np.nan
    with pytest.raises(ValueError, match=r"no 12 x 12 block of z has at least 50%"):
        fit_ground_to_valid_points(z, block=12)
    with pytest.raises(ValueError, match="must not hold inf"):
        fit_ground_to_valid_points(np.full((48, 48), np.inf))
    with pytest.raises(ValueError, match="constant"):
        fit_ground_to_valid_points(np.ones((48, 48)), block=12)
    with pytest.raises(ValueError, match="2-D height map"):
        fit_ground_to_valid_points(np.ones(48))


@pytest.mark.parametrize("nu", [0.5, 2.5])
def test_the_gradient_is_that_of_the_likelihood(nu):
    # central differences of the value itself (the optimiser's gradient must agree with them)
    z = _measured(seed=2, shape=(40, 40))
    valid = ~np.isnan(z)
    centred = np.where(valid, z - np.nanmean(z), 0.0)
    likelihood = BlockLikelihood(centred, valid, ((0, 0), (20, 12), (8, 24)), 14, np.ones(2), nu)
    u = likelihood.unconstrained({"variance": 3.0, "lambda_a": 9.0, "lambda_b": 4.0,
                                  "angle": -0.4, "noise_variance": 0.2})
    value, grad = likelihood.value_and_gradient(u)
    assert value == pytest.approx(likelihood.value(u), rel=1e-12)
    h = 1e-5
    numeric = [(likelihood.value(u + h * e) - likelihood.value(u - h * e)) / (2 * h)
               for e in np.eye(u.size)]
    assert np.allclose(grad, numeric, rtol=1e-5, atol=1e-5 * abs(value) * 1e-3)
    assert np.all(np.abs(grad) > 1e-3)            # no component trivially zero at this point
