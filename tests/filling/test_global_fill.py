"""Gap filling by the GP posterior (roughgp.filling.global_fill): CG against dense algebra."""

import math

import numpy as np
import pytest

from roughgp.filling.global_fill import ToeplitzOperator, conjugate_gradients, fill_gaps
from roughgp.gp.kernels import MaternKernel, RotatedExponentialKernel
from roughgp.sampling import grid_covariance, sample_grid

SHAPE = (20, 24)
KERNEL = RotatedExponentialKernel(10.0, (8.0, 2.0), math.pi / 6)


def _surface(noise_variance, seed=0, share=0.15, kernel=KERNEL):
    rng = np.random.default_rng(seed)
    g = sample_grid(kernel, SHAPE, method="circulant", seed=seed + 1)[0]
    z = g + math.sqrt(noise_variance) * rng.standard_normal(SHAPE)
    missing = rng.random(SHAPE) < share
    holed = z.copy()
    holed[missing] = np.nan
    return z, holed, missing


def _dense_posterior(kernel, z, missing, noise_variance):
    cov = grid_covariance(kernel, SHAPE)
    obs = ~missing.ravel()
    y = z.ravel()[obs]
    offset = y.mean()
    a = cov[np.ix_(obs, obs)] + noise_variance * np.eye(obs.sum())
    mean = cov[:, obs] @ np.linalg.solve(a, y - offset) + offset
    post = cov - cov[:, obs] @ np.linalg.solve(a, cov[obs, :])
    return mean.reshape(SHAPE), np.sqrt(np.clip(np.diag(post), 0, None)).reshape(SHAPE)


@pytest.mark.parametrize("kernel", [KERNEL, MaternKernel(nu=1.5, dim=2, variance=2.0,
                                                         lengthscale=3.0)])
def test_toeplitz_product_is_exact(kernel):
    v = np.random.default_rng(4).standard_normal(SHAPE)
    got = ToeplitzOperator(kernel, SHAPE).matvec(v)
    want = (grid_covariance(kernel, SHAPE) @ v.ravel()).reshape(SHAPE)
    assert np.max(np.abs(got - want)) < 1e-10 * np.max(np.abs(want))


@pytest.mark.parametrize("preconditioner", ["circulant", None])
def test_cg_mean_equals_dense_solve(preconditioner):
    z, holed, missing = _surface(0.1)
    fill = fill_gaps(holed, KERNEL, noise_variance=0.1, n_samples=0, tol=1e-12,
                     preconditioner=preconditioner)
    mean, _ = _dense_posterior(KERNEL, z, missing, 0.1)
    assert fill.converged and fill.iterations > 0
    assert np.max(np.abs(fill.mean - mean)) < 1e-6
    assert np.array_equal(fill.missing, missing)
    assert np.array_equal(fill.filled[~missing], z[~missing])
    assert np.array_equal(fill.filled[missing], fill.mean[missing])


def test_circulant_preconditioner_needs_fewer_iterations():
    _, holed, _ = _surface(0.01)
    plain = fill_gaps(holed, KERNEL, noise_variance=0.01, n_samples=0, preconditioner=None)
    pre = fill_gaps(holed, KERNEL, noise_variance=0.01, n_samples=0)
    assert pre.iterations < plain.iterations
    assert np.max(np.abs(pre.mean - plain.mean)) < 1e-4


def test_mask_marks_outliers_as_missing():
    z, holed, missing = _surface(0.1)
    spurious = np.zeros(SHAPE, dtype=bool)
    spurious[3, 4] = spurious[10, 11] = True
    spiked = holed.copy()
    spiked[spurious] = 1e3  # spurious points, ignored through the mask
    fill = fill_gaps(spiked, KERNEL, noise_variance=0.1, mask=spurious, n_samples=0, tol=1e-12)
    mean, _ = _dense_posterior(KERNEL, z, missing | spurious, 0.1)
    assert np.max(np.abs(fill.mean - mean)) < 1e-6
    assert np.array_equal(fill.missing, missing | spurious)


def test_observed_points_reproduced_and_sd_grows_into_holes():
    noise_variance = 1e-6
    z, holed, missing = _surface(noise_variance)
    fill = fill_gaps(holed, KERNEL, noise_variance=noise_variance, n_samples=32, seed=1,
                     tol=1e-10, sample_tol=1e-8, max_iter=5000, sample_dtype=np.float64)
    assert fill.converged
    assert np.max(np.abs(fill.mean - z)[~missing]) < 0.01
    assert np.max(fill.sd[~missing]) < 0.01
    assert np.min(fill.sd[missing]) > 0.1
    # sd matches the dense posterior sd to Monte Carlo accuracy (32 draws: ~13 % per point)
    _, sd = _dense_posterior(KERNEL, z, missing, noise_variance)
    ratio = fill.sd[missing] / sd[missing]
    assert abs(np.median(ratio) - 1) < 0.15


def test_sd_matches_dense_posterior_with_many_draws():
    z, holed, missing = _surface(0.1)
    fill = fill_gaps(holed, KERNEL, noise_variance=0.1, n_samples=400, seed=5, sample_tol=1e-8,
                     sample_dtype=np.float64)
    _, sd = _dense_posterior(KERNEL, z, missing, 0.1)
    # 400 draws: relative sd error ~ 1 / sqrt(800) = 3.5 %; 5 sigma for the worst of 480 points
    assert np.max(np.abs(fill.sd / sd - 1)) < 0.2
    assert abs(np.mean(fill.sd / sd) - 1) < 0.02


def test_deterministic_by_seed():
    _, holed, _ = _surface(0.1)
    a = fill_gaps(holed, KERNEL, noise_variance=0.1, n_samples=4, seed=7)
    b = fill_gaps(holed, KERNEL, noise_variance=0.1, n_samples=4, seed=7)
    c = fill_gaps(holed, KERNEL, noise_variance=0.1, n_samples=4, seed=8)
    assert np.array_equal(a.mean, b.mean) and np.array_equal(a.sd, b.sd)
    assert not np.array_equal(a.sd, c.sd)
    assert np.array_equal(a.mean, c.mean)


def test_single_precision_draws_change_the_sd_far_less_than_its_monte_carlo_error():
    _, holed, missing = _surface(0.1)
    single = fill_gaps(holed, KERNEL, noise_variance=0.1, n_samples=16, seed=3)
    double = fill_gaps(holed, KERNEL, noise_variance=0.1, n_samples=16, seed=3,
                       sample_dtype=np.float64)
    assert single.converged and double.converged
    assert np.array_equal(single.mean, double.mean)  # the mean is always solved in float64
    # the same draws, solved to 1e-3 in either precision: the sd's relative Monte Carlo
    # error with 16 draws is 1/sqrt(32) = 18 %; single precision must stay far below it
    assert np.max(np.abs(single.sd[missing] / double.sd[missing] - 1)) < 0.01


def test_conjugate_gradients_batched():
    rng = np.random.default_rng(0)
    m = rng.standard_normal((30, 30))
    a = m @ m.T + 30 * np.eye(30)
    b = rng.standard_normal((3, 30))
    x, iterations, done = conjugate_gradients(lambda v: v @ a.T, b, tol=[1e-12, 1e-3, 1e-12])
    assert np.all(done)
    assert iterations[1] < iterations[0]
    assert np.allclose(x[0], np.linalg.solve(a, b[0]), atol=1e-9)


@pytest.mark.parametrize("z, kwargs, match", [
    (np.full(SHAPE, np.nan), {}, "no valid"),
    (np.zeros(SHAPE), {}, "no missing"),
    (np.zeros(10), {}, "z must be a 2-D"),
    (np.zeros((1, 10)), {}, "z must be a 2-D"),
    (np.where(np.eye(20, 24) > 0, np.inf, 0.0), {}, "inf"),
    (None, {"noise_variance": -1.0}, "noise_variance"),
    (None, {"noise_variance": np.nan}, "noise_variance"),
    (None, {"mask": np.zeros((3, 3), dtype=bool)}, "mask must have the shape"),
    (None, {"mask": np.zeros(SHAPE)}, "mask must be a boolean"),
    (None, {"n_samples": -1}, "n_samples"),
    (None, {"n_samples": 2.5}, "n_samples"),
    (None, {"tol": 0.0}, "tol"),
    (None, {"sample_tol": -1.0}, "sample_tol"),
    (None, {"max_iter": 0}, "max_iter"),
    (None, {"preconditioner": "jacobi"}, "preconditioner"),
    (None, {"sample_dtype": np.float16}, "sample_dtype must be numpy.float32 or"),
    (None, {"n_samples": 2, "sample_tol": 1e-8}, r"sample_tol must be >= 1e-05 with sample_dtype"),
    (None, {"seed": -3}, "seed"),
])
def test_bad_input_raises(z, kwargs, match):
    if z is None:
        _, z, _ = _surface(0.1)
    kwargs = {"noise_variance": 0.1, "n_samples": 0, **kwargs}
    with pytest.raises(ValueError, match=match):
        fill_gaps(z, KERNEL, **kwargs)


def test_non_convergence_is_reported():
    _, holed, _ = _surface(0.1)
    fill = fill_gaps(holed, KERNEL, noise_variance=0.1, n_samples=0, max_iter=1,
                     preconditioner=None)
    assert not fill.converged and fill.iterations == 1
    assert np.all(np.isfinite(fill.mean))
