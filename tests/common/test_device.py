"""Tests of the ``device=`` paths (roughgp.common.device): torch on the CPU against the numpy paths,
and, where torch sees a GPU, the same checks on ``"cuda"`` (skipped without one).

The torch paths must give the numbers of the numpy paths where both draw the same noise
(dense Cholesky and Lanczos draws, likelihoods, the gap-filling mean), the right covariance
where the noise comes from a device generator (circulant draws), and the same array for the
same seed.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import torch

from roughgp import sampling
from roughgp.cli.main import main
from roughgp.common import device as dev
from roughgp.filling import global_fill as gap_filling
from roughgp.gp import kernels, toeplitz
from roughgp.inference import fitting, posterior, whittle_fit
from roughgp.models import surfaces

HAS_CUDA = torch.cuda.is_available()
DEVICES = ["cpu", pytest.param("cuda", marks=pytest.mark.skipif(
    not HAS_CUDA, reason="torch sees no CUDA device"))]


def _kernel():
    return kernels.RotatedExponentialKernel(variance=2.0, lengthscales=(6.0, 2.0),
                                            angle=math.pi / 6)


# ------------------------------------------------------------------ resolve


def test_resolve_accepts_none_and_cpu():
    assert dev.resolve(None) is None
    assert dev.resolve("cpu") == torch.device("cpu")
    assert dev.resolve(torch.device("cpu")) == torch.device("cpu")
    assert "cpu" in dev.available()


@pytest.mark.parametrize("bad", ["gpu", "mps", 3, 1.5, ["cpu"]])
def test_resolve_rejects_unknown_devices_by_name(bad):
    with pytest.raises(ValueError, match=r"^dev must be None"):
        dev.resolve(bad, name="dev")


@pytest.mark.skipif(HAS_CUDA, reason="the message is for machines without a GPU")
def test_resolve_says_when_there_is_no_gpu():
    with pytest.raises(ValueError, match=r"device='cuda' but torch sees no CUDA device"):
        dev.resolve("cuda")


@pytest.mark.skipif(not HAS_CUDA, reason="torch sees no CUDA device")
def test_resolve_rejects_a_gpu_index_beyond_the_count():
    count = torch.cuda.device_count()
    with pytest.raises(ValueError, match=rf"only {count} CUDA device"):
        dev.resolve(f"cuda:{count}")


def test_check_memory_refuses_before_allocating():
    with pytest.raises(ValueError, match=r"the test array needs about .* GiB on cpu"):
        dev.check_memory(2**60, torch.device("cpu"), "the test array")


# ------------------------------------------------------------------ sampling


@pytest.mark.parametrize("device", DEVICES)
@pytest.mark.parametrize("method", ["cholesky", "lanczos"])
def test_dense_draws_match_numpy(device, method):
    kernel = _kernel()
    a = sampling.sample_grid(kernel, (12, 10), n_samples=3, method=method, seed=5, rank=40)
    b = sampling.sample_grid(kernel, (12, 10), n_samples=3, method=method, seed=5, rank=40,
                             device=device)
    assert isinstance(b, np.ndarray) and b.dtype == np.float64 and b.shape == (3, 12, 10)
    np.testing.assert_allclose(b, a, rtol=0, atol=1e-9 * math.sqrt(2.0))


@pytest.mark.parametrize("device", DEVICES)
def test_circulant_draws_are_seeded(device):
    kernel = _kernel()
    a = sampling.sample_grid(kernel, (40, 30), n_samples=3, method="circulant", seed=2,
                             device=device)
    b = sampling.sample_grid(kernel, (40, 30), n_samples=3, method="circulant", seed=2,
                             device=device)
    c = sampling.sample_grid(kernel, (40, 30), n_samples=3, method="circulant", seed=3,
                             device=device)
    assert a.shape == (3, 40, 30) and isinstance(a, np.ndarray)
    np.testing.assert_array_equal(a, b)
    assert np.max(np.abs(a - c)) > 0.5


@pytest.mark.parametrize("device", DEVICES)
@pytest.mark.parametrize("dtype", [np.float64, np.float32])
def test_circulant_draws_have_the_kernel_covariance(device, dtype):
    # 4000 draws of a 6 x 5 grid: the sample covariance against eq 10's R, entry by entry,
    # within 5 standard errors (the standard error of a covariance estimate is at most
    # sqrt((r_ii r_jj + r_ij^2) / n))
    kernel, shape, n = _kernel(), (6, 5), 4000
    draws = sampling.sample_grid(kernel, shape, n_samples=n, method="circulant", seed=11,
                                 dtype=dtype, device=device)
    assert draws.dtype == dtype
    flat = draws.reshape(n, -1).astype(np.float64)
    estimate = flat.T @ flat / n
    truth = sampling.grid_covariance(kernel, shape)
    d = np.diag(truth)
    stderr = np.sqrt((np.outer(d, d) + truth**2) / n)
    assert np.all(np.abs(estimate - truth) < 5 * stderr)


def test_additive_kernel_on_a_device():
    kx = kernels.MaternKernel(nu=0.5, variance=1.0, lengthscale=4.0, dim=1)
    ky = kernels.MaternKernel(nu=0.5, variance=0.5, lengthscale=2.0, dim=1)
    additive = kernels.AdditiveKernel(kx, ky)
    draws = sampling.sample_grid(additive, (20, 30), n_samples=400, method="circulant",
                                 seed=1, device="cpu")
    # eq 22: the variance is the sum of the two parts' (1.5), within 5 standard errors
    # of the mean of 400 x 600 correlated values (loosely bounded by 400 independent ones)
    assert abs(draws.var() - 1.5) < 5 * 1.5 * math.sqrt(2 / 400)


def test_ground_and_honed_pass_the_device_on():
    a = surfaces.ground((32, 32), variance=1.0, lengthscales=(8.0, 2.0), angle=0.3, seed=4,
                        method="cholesky")
    b = surfaces.ground((32, 32), variance=1.0, lengthscales=(8.0, 2.0), angle=0.3, seed=4,
                        method="cholesky", device="cpu")
    np.testing.assert_allclose(b, a, atol=1e-9)
    with pytest.raises(ValueError, match=r"device must be None"):
        surfaces.honed((16, 16), surfaces.FIGURE_3, seed=1, device="gpu")


def test_dense_draw_refuses_a_grid_beyond_memory():
    with pytest.raises(ValueError, match=r"method='cholesky' on shape \(2000, 2000\).*GiB on cpu"):
        sampling.sample_grid(_kernel(), (2000, 2000), method="cholesky", device="cpu")


@pytest.mark.skipif(not HAS_CUDA, reason="torch sees no CUDA device")
def test_cuda_and_cpu_circulant_streams_agree_in_distribution():
    kernel = _kernel()
    a = sampling.sample_grid(kernel, (256, 256), n_samples=8, method="circulant", seed=1,
                             device="cuda")
    b = sampling.sample_grid(kernel, (256, 256), n_samples=8, method="circulant", seed=1,
                             device="cpu")
    # different generators, same distribution: the variances of 8 x 65536 correlated points
    assert not np.allclose(a, b)
    assert abs(a.var() / b.var() - 1) < 0.1


# ------------------------------------------------------------------ likelihood


@pytest.mark.parametrize("device", DEVICES)
def test_grid_likelihood_matches_numpy(device):
    z = surfaces.ground((20, 24), variance=2.0, lengthscales=(6.0, 2.0), angle=0.5,
                        noise_variance=0.1, seed=3)
    z = z - z.mean()
    params = {"variance": 2.0, "lambda_a": 6.0, "lambda_b": 2.0, "angle": 0.5,
              "noise_variance": 0.1}
    a = posterior.ground_patch_model(z).log_likelihood(params)
    b = posterior.ground_patch_model(z, device=device).log_likelihood(params)
    assert abs(b - a) < 1e-9 * abs(a)


@pytest.mark.parametrize("device", DEVICES)
def test_grid_likelihood_refuses_an_indefinite_covariance(device):
    z = np.random.default_rng(0).standard_normal((6, 6))
    loglik = posterior.grid_likelihood(z, 1.0, lambda p: (lambda lags: -np.ones(lags.shape[:-1])),
                                       device=device)
    with pytest.raises(ValueError, match="not positive definite"):
        loglik({})


def test_grid_likelihood_on_a_device_lifts_the_patch_limit():
    z = np.random.default_rng(1).standard_normal((64, 65))  # 4160 > MAX_GRID_POINTS
    with pytest.raises(ValueError, match="at most MAX_GRID_POINTS"):
        posterior.grid_likelihood(z, 1.0, lambda p: _kernel())
    loglik = posterior.grid_likelihood(z, 1.0, lambda p: _kernel(), device="cpu")
    assert math.isfinite(loglik({"noise_variance": 1.0}))
    with pytest.raises(ValueError, match=r"the dense likelihood of a 400 x 400 patch needs"):
        posterior.grid_likelihood(np.zeros((400, 400)), 1.0, lambda p: _kernel(), device="cpu")


@pytest.mark.parametrize("device", DEVICES)
def test_profile_likelihood_and_gradient_match_the_recursion(device):
    n = 300
    lags = np.arange(n)
    r = np.exp(-lags / 10.0) * np.cos(lags / 7.0)
    r[0] += 0.1
    z = np.random.default_rng(0).standard_normal(n)
    a, ga = toeplitz.toeplitz_log_likelihood(z, r, gradient=True)
    b, gb = toeplitz.toeplitz_log_likelihood(z, r, gradient=True, device=device)
    assert abs(b - a) < 1e-9 * abs(a)
    np.testing.assert_allclose(gb, ga, rtol=0, atol=1e-9 * np.abs(ga).max())
    with pytest.raises(ValueError, match="must be positive definite"):
        toeplitz.toeplitz_log_likelihood(z, -r, device=device)


def _two_line_profile(n, seed=1):
    kernel = kernels.SpectralMixtureKernel(2, dim=1, weights=[1.0, 0.3],
                                           means=[[0.05], [0.2]], variances=[[1e-6], [1e-4]])
    z = sampling.sample_grid(kernel, (n,), seed=seed, method="circulant")[0]
    return np.arange(n, dtype=np.float64), z + 0.1 * np.random.default_rng(seed).standard_normal(n)


@pytest.mark.parametrize("device", DEVICES)
def test_spectral_mixture_fit_on_a_device_follows_the_same_path(device):
    x, z = _two_line_profile(256)
    a = fitting.fit_spectral_mixture(x, z, 2, seed=0, n_candidates=4)
    b = fitting.fit_spectral_mixture(x, z, 2, seed=0, n_candidates=4,
                                     device=device)
    # the same candidates, likelihoods and gradients (to ~1e-11); rounding can still change
    # L-BFGS-B's steps (here the screen stops at an iteration limit), so the fits must agree
    # as optimisers do: on the same optimum to far below a thousandth of a log unit
    assert [c.initial_log_likelihood for c in b.candidates] == pytest.approx(
        [c.initial_log_likelihood for c in a.candidates], rel=1e-9)
    assert b.chosen == a.chosen
    assert abs(b.log_marginal_likelihood - a.log_marginal_likelihood) < 1e-3
    np.testing.assert_allclose(b.means, a.means, rtol=1e-3)


@pytest.mark.parametrize("device", DEVICES)
def test_whittle_likelihood_and_fit_on_a_device_follow_the_cpu(device):
    """The debiased Whittle likelihood (issue 40) on a device: the same value and gradient as
    torch on the CPU (to rounding), and the same optimum of a fit with holes."""
    kernel = kernels.RotatedExponentialKernel(variance=2.0, lengthscales=(6.0, 2.0), angle=0.5)
    z = sampling.sample_grid(kernel, (48, 56), seed=3, method="circulant")[0]
    holes = np.random.default_rng(3).random(z.shape) < 0.1
    valid = ~holes
    u = np.array([0.5, 1.5, 0.6, 0.3, -2.0])
    here = whittle_fit.WhittleLikelihood(z - z.mean(), valid, (1.0, 1.0))
    there = whittle_fit.WhittleLikelihood(z - z.mean(), valid, (1.0, 1.0), device=device)
    value, grad = here.value_and_gradient(u)
    value_d, grad_d = there.value_and_gradient(u)
    assert value_d == pytest.approx(value, rel=1e-11)
    np.testing.assert_allclose(grad_d, grad, rtol=1e-8, atol=1e-8)
    a = whittle_fit.fit_whittle(np.where(holes, np.nan, z))
    b = whittle_fit.fit_whittle(np.where(holes, np.nan, z), device=device)
    assert abs(b.log_likelihood - a.log_likelihood) < 1e-6
    assert b.groove.variance == pytest.approx(a.groove.variance, rel=1e-4)
    assert b.groove.lengthscales == pytest.approx(a.groove.lengthscales, rel=1e-4)


def test_the_block_fit_refuses_a_device():
    from roughgp.surface_models.fit import fit_surface_model
    z = np.random.default_rng(0).standard_normal((32, 32))
    with pytest.raises(ValueError, match="device='cpu' applies to likelihood='whittle' only"):
        fit_surface_model(z, device="cpu")


def test_whittle_fit_refuses_a_map_beyond_memory(monkeypatch):
    monkeypatch.setattr(dev, "free_bytes", lambda device: 10 * 2**20)
    with pytest.raises(ValueError, match="the Whittle likelihood needs about .* GiB on cpu"):
        whittle_fit.fit_whittle(np.random.default_rng(0).standard_normal((256, 256)),
                                device="cpu")


# ------------------------------------------------------------------ gap filling


@pytest.mark.parametrize("device", DEVICES)
def test_fill_gaps_on_a_device_matches_numpy(device):
    kernel = kernels.RotatedExponentialKernel(variance=4.0, lengthscales=(20.0, 5.0),
                                              angle=0.5)
    truth = surfaces.ground((64, 80), variance=4.0, lengthscales=(20.0, 5.0), angle=0.5,
                            noise_variance=0.05, seed=2)
    z = truth.copy()
    z[np.random.default_rng(0).random(z.shape) < 0.1] = np.nan
    z[30:36, 10:60] = np.nan
    a = gap_filling.fill_gaps(z, kernel, noise_variance=0.05, n_samples=8, seed=1)
    b = gap_filling.fill_gaps(z, kernel, noise_variance=0.05, n_samples=8, seed=1,
                              device=device)
    assert b.converged and isinstance(b.mean, np.ndarray)
    # both solves stop at a relative residual of 1e-6: the means agree far below the sd
    assert np.max(np.abs(b.mean - a.mean)) < 1e-3 * a.sd[a.missing].mean()
    # the sd is a Monte Carlo estimate from other prior draws: same level within its
    # sampling error (8 draws: about 1/sqrt(16) per point, far less averaged over the gaps)
    assert abs(b.sd[b.missing].mean() / a.sd[a.missing].mean() - 1) < 0.1


# ------------------------------------------------------------------ command


def test_cli_rejects_an_unknown_device(capsys, tmp_path):
    code = main(["simulate", "ground", "--shape", "8", "8", "--seed", "1", "--out",
                 str(tmp_path / "z.npy"), "--device", "gpu"])
    assert code == 2
    assert "--device must be None, 'cpu', 'cuda' or 'cuda:N', got 'gpu'" in capsys.readouterr().err


def test_cli_simulates_on_the_cpu_device(capsys, tmp_path):
    path = tmp_path / "z.npy"
    code = main(["simulate", "ground", "--shape", "16", "24", "--seed", "1", "--out", str(path),
                 "--method", "cholesky", "--device", "cpu"])
    assert code == 0, capsys.readouterr().err
    reference = tmp_path / "r.npy"
    assert main(["simulate", "ground", "--shape", "16", "24", "--seed", "1", "--out",
                 str(reference), "--method", "cholesky"]) == 0
    np.testing.assert_allclose(np.load(path), np.load(reference), atol=1e-9)
