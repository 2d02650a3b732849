"""Tests of the noise model (eq 8), the covariance-error diagnostics (section 3.1) and the
FFT-filter baseline."""

import math

import numpy as np
import pytest

from roughgp import sampling
from roughgp.gp import kernels, noise
from roughgp.sampling import diagnostics, fft_filter


def test_gaussian_noise_adds_its_variance_and_is_seeded():
    model = noise.GaussianNoise(2.0)
    latent = np.zeros((200, 100))
    z = model.sample(latent, seed=3)
    assert z.shape == latent.shape
    # variance of 20 000 N(0, 2) draws: standard error 2 * sqrt(2 / 20000) = 0.02
    assert abs(z.var() - 2.0) < 5 * 0.02
    np.testing.assert_array_equal(z, model.sample(latent, seed=3))
    assert not np.array_equal(z, model.sample(latent, seed=4))
    assert model.variance == 2.0
    np.testing.assert_array_equal(noise.GaussianNoise(0.0).sample(latent + 1.5, seed=1), latent + 1.5)


@pytest.mark.parametrize("bad", [-1.0, float("nan"), float("inf")])
def test_gaussian_noise_rejects_bad_variance(bad):
    with pytest.raises(ValueError, match="variance"):
        noise.GaussianNoise(bad)


def test_gaussian_noise_rejects_nonfinite_latent():
    with pytest.raises(ValueError, match="latent"):
        noise.GaussianNoise(1.0).sample(np.array([0.0, np.nan]))


def test_noise_model_is_an_interface():
    with pytest.raises(TypeError):
        noise.NoiseModel()


def test_sample_covariance_matches_numpy_cov():
    x = np.random.default_rng(0).normal(size=(30, 4, 5))
    np.testing.assert_allclose(diagnostics.sample_covariance(x), np.cov(x.reshape(30, -1).T),
                               atol=1e-12)


def test_covariance_error_is_zero_for_the_sample_covariance_itself():
    x = np.random.default_rng(1).normal(size=(10, 6))
    assert diagnostics.covariance_error(x, diagnostics.sample_covariance(x)) == pytest.approx(0)


def test_expected_covariance_error_matches_exact_draws():
    # 200 experiments of 50 exact draws: the mean error must match the Wishart prediction
    kernel = kernels.MaternKernel(nu=0.5, variance=3.0, lengthscale=2.0)
    covariance = sampling.grid_covariance(kernel, (8,))
    draws = sampling.sample_grid(kernel, (8,), n_samples=200 * 50, method="cholesky", seed=5)
    errors = [diagnostics.covariance_error(draws[i::200], covariance) for i in range(200)]
    expected = diagnostics.expected_covariance_error(covariance, 50)
    # the normal approximation of each entry is good to a few per cent for n - 1 = 49
    assert abs(np.mean(errors) / expected - 1) < 0.05
    assert expected == pytest.approx(
        math.sqrt(2 / math.pi) * np.mean(np.sqrt(covariance**2 + np.outer(np.diag(covariance),
                                                                              np.diag(covariance))))
        / math.sqrt(49))


def test_diagnostics_reject_bad_input():
    with pytest.raises(ValueError, match="samples"):
        diagnostics.sample_covariance(np.zeros((1, 4)))
    with pytest.raises(ValueError, match="covariance"):
        diagnostics.covariance_error(np.zeros((5, 4)), np.eye(3))
    with pytest.raises(ValueError, match="n_samples"):
        diagnostics.expected_covariance_error(np.eye(3), 1)


def test_fft_filter_matches_short_range_covariance_and_is_seeded():
    kernel = kernels.MaternKernel(nu=math.inf, dim=2, variance=2.0, lengthscale=1.5)
    z = fft_filter.fft_filter(kernel.psd, (32, 32), n_samples=400, seed=2)
    assert z.shape == (400, 32, 32)
    np.testing.assert_array_equal(z[:3], fft_filter.fft_filter(kernel.psd, (32, 32), n_samples=3,
                                                               seed=2))
    # a short-range ACVF on a large grid: variance and lag-1 covariance close to the kernel's
    assert abs(z.var() - 2.0) < 0.1
    lag1 = np.mean(z[:, :, 1:] * z[:, :, :-1])
    assert abs(lag1 - float(kernel.acvf(np.array([[1.0, 0.0]]))[0])) < 0.1


def test_fft_filter_is_periodic_unlike_eq_10():
    # a long lengthscale wraps around: the two ends of a profile are strongly correlated
    kernel = kernels.MaternKernel(nu=0.5, variance=1.0, lengthscale=50.0)
    z = fft_filter.fft_filter(kernel.psd, (64,), n_samples=2000, seed=4)
    end_to_end = np.mean(z[:, 0] * z[:, -1]) / z.var()
    true_correlation = float(kernel.acvf(np.array([[63.0]]))[0])  # exp(-63/50) = 0.28 under eq 10
    assert true_correlation < 0.3 and end_to_end > 0.8  # the torus makes them neighbours


def test_fft_filter_rejects_bad_input():
    with pytest.raises(ValueError, match="n_samples"):
        fft_filter.fft_filter(lambda f: np.ones(f.shape[:-1]), (8,), n_samples=0)
    with pytest.raises(ValueError, match="psd"):
        fft_filter.fft_filter(lambda f: -np.ones(f.shape[:-1]), (8,))


# ------------------------------------------------------------- spread of one surface's statistics

@pytest.mark.parametrize("shape, spacing", [((7,), 0.7), ((6, 5), (0.5, 1.2)), ((4, 9), 1.0)])
def test_grid_mean_variance_and_sample_variance_sd_match_the_dense_sums(shape, spacing):
    if len(shape) == 1:
        kernel = kernels.MaternKernel(0.5, lengthscale=2.0, variance=2.0)
    else:
        kernel = kernels.RotatedExponentialKernel(2.0, (3.0, 1.5), 0.5)
    r = sampling.grid_covariance(kernel, shape, spacing=spacing) + 0.3 * np.eye(int(np.prod(shape)))
    n = len(r)
    assert diagnostics.grid_mean_variance(kernel, shape, spacing, noise_variance=0.3) == \
        pytest.approx(r.sum() / n**2, rel=1e-12)
    assert diagnostics.sample_variance_sd(kernel, shape, spacing, noise_variance=0.3) == \
        pytest.approx(math.sqrt(2 * (r**2).sum()) / n, rel=1e-12)


def test_sample_variance_sd_predicts_the_spread_of_draws():
    kernel = kernels.RotatedExponentialKernel(1.0, (6.0, 2.0), 0.4)
    shape = (32, 32)
    draws = sampling.sample_grid(kernel, shape, n_samples=400, method="circulant", seed=11)
    variances = (draws**2).mean(axis=(1, 2))  # about the known zero mean
    predicted = diagnostics.sample_variance_sd(kernel, shape)
    # the sd of 400 variances is within ~3.5 % of the truth (chi-like, heavier tail): 20 % margin
    assert variances.std(ddof=1) == pytest.approx(predicted, rel=0.2)
    means = draws.mean(axis=(1, 2))
    assert means.var(ddof=1) == pytest.approx(diagnostics.grid_mean_variance(kernel, shape),
                                              rel=0.25)  # sd of a 400-draw variance: 7 %
