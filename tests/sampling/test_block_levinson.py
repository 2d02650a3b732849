"""The block Levinson route of the Cholesky draw (roughgp.sampling.block_levinson): the same
factor as the dense Cholesky factorisation, so the same seed gives the same draw to rounding;
a covariance it cannot factorise goes to the dense route and its jitter policy."""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

from roughgp.common.grid import normalize
from roughgp.gp.numpy_kernels import MaternACVF
from roughgp.models import surfaces
from roughgp.sampling import block_levinson, grid_sampler, sample_grid

KERNELS = {
    "figure 3 step 1": surfaces.FIGURE_3[0].covariance(),
    "figure 3 step 2, mirrored": surfaces.FIGURE_3[1].covariance(mirrored=True),
    "figure 2": surfaces.FIGURE_2.covariance(),
    "Matern 5/2": MaternACVF(variance=2.0, lengthscale=6.0, nu=2.5, dim=2),
}


def _table(kernel, shape):
    return grid_sampler._lag_table(kernel, shape, normalize(shape, 1.0)[1])


@pytest.mark.parametrize("name", KERNELS)
@pytest.mark.parametrize("shape", [(24, 20), (9, 31)])
def test_the_factor_is_the_dense_cholesky_factor(name, shape):
    table = _table(KERNELS[name], shape)
    covariance = grid_sampler._gathered(table, shape)
    factor = block_levinson.factorise(table, shape)
    lower = factor @ np.eye(covariance.shape[0])
    dense = np.linalg.cholesky(covariance)
    scale = np.abs(covariance).max()
    assert np.abs(np.triu(lower, 1)).max() == 0.0  # lower triangular
    np.testing.assert_allclose(lower @ lower.T, covariance, rtol=0, atol=1e-12 * scale)
    np.testing.assert_allclose(lower, dense, rtol=0, atol=1e-9 * np.abs(dense).max())


def test_a_wrong_table_is_caught():
    """Calibration: the comparison above fails for the factor of another covariance."""
    shape = (24, 20)
    factor = block_levinson.factorise(_table(KERNELS["figure 2"], shape), shape)
    lower = factor @ np.eye(480)
    other = grid_sampler._gathered(_table(KERNELS["figure 3 step 1"], shape), shape)
    assert np.abs(lower @ lower.T - other).max() > 0.1 * np.abs(other).max()


def test_sample_grid_draws_what_the_dense_factor_draws():
    """64 x 64 (the block route) against the dense factor applied to the same noise."""
    kernel, shape = KERNELS["figure 3 step 1"], (64, 64)
    assert block_levinson.worthwhile(shape)
    grid_sampler._FACTORS.clear()
    z, info = sample_grid(kernel, shape, method="cholesky", seed=4, return_info=True)
    assert info.jitter == 0.0
    dense = np.linalg.cholesky(grid_sampler._gathered(_table(kernel, shape), shape))
    expected = (dense @ np.random.default_rng(4).standard_normal((4096, 1))).T.reshape(1, 64, 64)
    np.testing.assert_allclose(z, expected, rtol=0, atol=1e-9 * np.abs(expected).max())
    other = sample_grid(kernel, shape, method="cholesky", seed=5)
    assert np.abs(other - expected).max() > 0.1 * np.abs(expected).max()


def test_a_singular_covariance_goes_to_the_dense_route_and_its_jitter():
    shape = (20, 20)
    ones = np.ones((39, 39))  # a perfectly correlated field: R = 1 1^T, singular
    assert block_levinson.factorise(ones, shape) is None
    smooth = MaternACVF(variance=1.0, lengthscale=3.0, nu=math.inf, dim=2)
    grid_sampler._FACTORS.clear()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        z, info = sample_grid(smooth, (30, 30), method="cholesky", seed=1, return_info=True)
    assert info.jitter > 0 and np.all(np.isfinite(z))  # the dense policy's jitter


@pytest.mark.parametrize("shape, expected", [((64, 64), True), ((48, 40), True),
                                             ((5, 7), False), ((24, 24), False),
                                             ((4096,), False), ((2, 900), False)])
def test_the_route_is_taken_where_it_is_cheaper(shape, expected):
    assert block_levinson.worthwhile(shape) is expected


def test_a_honed_surface_factorises_its_long_step_once_by_blocks(monkeypatch):
    calls = []
    original = block_levinson.factorise

    def count(table, shape):
        calls.append(shape)
        return original(table, shape)
    monkeypatch.setattr(block_levinson, "factorise", count)
    grid_sampler._FACTORS.clear()
    grid_sampler._CHOICES.clear()
    z = surfaces.honed((64, 64), surfaces.FIGURE_3, seed=1, method="auto")
    assert np.all(np.isfinite(z)) and calls == [(64, 64)]  # step 1's +phi and -phi
