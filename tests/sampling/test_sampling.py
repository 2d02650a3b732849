"""Tests of roughgp.sampling and roughgp.sampling.circulant: draws of eq 10, G ~ N(0, R), on a grid
(Jawaid & Seewig, section 2.2 and section 3.1 / figure 2).

The statistical tests compare the sample covariance of many draws with R entry by entry:
for zero-mean Gaussians, C_ij = mean_s(g_i g_j) has variance (R_ij^2 + R_ii R_jj) / n, so
z_ij = (C_ij - R_ij) / sqrt((R_ij^2 + R_ii R_jj) / n) is approximately standard normal. The
largest |z_ij| over the m = N (N + 1) / 2 distinct entries is compared with the Bonferroni
threshold Phi^-1(1 - alpha / (2 m)) for a family-wise false-alarm rate alpha = 1e-3 (valid
under any dependence between the entries; the normal approximation of a mean of n = 4000
products is the only approximation). Seeds are fixed, so each test is deterministic; the
false-alarm rate says how unlucky a seed would have to be. Each test also checks its power:
the same draws are rejected against the covariance of a WRONG kernel (lengthscale doubled).
"""

from __future__ import annotations

import math
import re
import time
import warnings

import numpy as np
import pytest
from scipy import stats

from roughgp import sampling
from roughgp.gp.kernels import (
    AdditiveKernel,
    MaternKernel,
    RotatedExponentialKernel,
    SpectralMixtureKernel,
)
from roughgp.sampling import (
    choose_method,
    circulant,
    grid_covariance,
    grid_sampler,
    sample_grid,
    truncation,
)

PI = math.pi
ALPHA = 1e-3  # family-wise false-alarm rate of each covariance test
N_DRAWS = 4000


# --------------------------------------------------------------------------- helpers

def _exp1d(lengthscale=3.0, variance=1.0):
    return MaternKernel(nu=0.5, dim=1, variance=variance, lengthscale=lengthscale)


def _rot(lengthscales=(3.0, 1.5), variance=2.0, angle=PI / 6):
    return RotatedExponentialKernel(variance, lengthscales, angle)


def _bonferroni_threshold(n_points, alpha=ALPHA):
    m = n_points * (n_points + 1) // 2
    return float(stats.norm.isf(alpha / (2 * m)))


def _max_z(samples, covariance):
    """Largest standardised deviation of the (known zero-mean) sample covariance from R."""
    g = samples.reshape(samples.shape[0], -1).astype(np.float64)
    n = g.shape[0]
    sample_cov = g.T @ g / n
    d = np.diag(covariance)
    se = np.sqrt((covariance**2 + np.outer(d, d)) / n)
    z = (sample_cov - covariance) / se
    return float(np.abs(z[np.triu_indices(len(d))]).max())


def _assert_covariance_matches(samples, kernel, wrong_kernel, shape, spacing=1.0):
    n_points = int(np.prod(shape))
    threshold = _bonferroni_threshold(n_points)
    z_true = _max_z(samples, grid_covariance(kernel, shape, spacing))
    assert z_true < threshold, f"max |z| = {z_true:.2f} >= {threshold:.2f} (alpha = {ALPHA})"
    z_wrong = _max_z(samples, grid_covariance(wrong_kernel, shape, spacing))
    assert z_wrong > threshold, f"no power: wrong kernel max |z| = {z_wrong:.2f}"


# 1-D exponential on 12 points; 2-D rotated exponential (eq 18) on a 5 x 6 grid with unequal
# spacing (dy, dx), so that a mix-up of axes or of the (x, y) component order is detected.
CASES = {
    "1d": dict(kernel=lambda: _exp1d(3.0), wrong=lambda: _exp1d(6.0), shape=(12,),
               spacing=1.0),
    "2d": dict(kernel=lambda: _rot((3.0, 1.5)), wrong=lambda: _rot((6.0, 3.0)), shape=(5, 6),
               spacing=(1.0, 0.8)),
}


# --------------------------------------------------------------------------- covariance of draws

@pytest.mark.parametrize("case", sorted(CASES))
@pytest.mark.parametrize("method", ["cholesky", "lanczos", "circulant"])
def test_sample_covariance_matches_grid_covariance(method, case):
    c = CASES[case]
    kernel, shape, spacing = c["kernel"](), c["shape"], c["spacing"]
    n_points = int(np.prod(shape))
    kwargs = dict(rank=n_points) if method == "lanczos" else {}  # full rank: exact
    samples, info = sample_grid(kernel, shape, spacing=spacing, n_samples=N_DRAWS, method=method,
                                seed=20240 + len(case) + len(method), return_info=True, **kwargs)
    assert samples.shape == (N_DRAWS, *shape) and samples.dtype == np.float64
    assert info.method == method
    if method == "lanczos":
        assert info.kept_trace_fraction == pytest.approx(1.0, abs=1e-8)
        assert info.details["rank"] == n_points
    if method == "circulant":
        assert info.clipped_fraction == 0.0 and info.min_eigenvalue >= -1e-10
    _assert_covariance_matches(samples, kernel, c["wrong"](), shape, spacing)


def test_float32_circulant_draws_keep_their_covariance():
    c = CASES["2d"]
    kernel, shape, spacing = c["kernel"](), c["shape"], c["spacing"]
    samples = sample_grid(kernel, shape, spacing=spacing, n_samples=N_DRAWS, method="circulant",
                          seed=77, dtype=np.float32)
    assert samples.dtype == np.float32 and samples.shape == (N_DRAWS, *shape)
    _assert_covariance_matches(samples, kernel, c["wrong"](), shape, spacing)


def test_grid_covariance_layout_and_values():
    """R[i, j] = r(x_j - x_i) with points in row-major order and lags in (x, y) order."""
    kernel, shape, spacing = _rot((3.0, 1.5)), (3, 4), (0.5, 2.0)
    cov = grid_covariance(kernel, shape, spacing)
    assert cov.shape == (12, 12)
    iy, ix = np.unravel_index(np.arange(12), shape)
    points = np.stack([ix * spacing[1], iy * spacing[0]], axis=-1)
    lags = points[None, :, :] - points[:, None, :]
    np.testing.assert_allclose(cov, kernel.acvf(lags), rtol=1e-14, atol=0)
    np.testing.assert_allclose(cov, cov.T, rtol=0, atol=0)


# --------------------------------------------------------------------------- lanczos

def test_lanczos_low_rank_loses_trace_and_gains_with_rank():
    kernel, shape = _rot((500.0, 5.0), variance=10.0), (12, 12)
    kept = []
    for rank in (2, 5, 10, 20):
        samples, info = sample_grid(kernel, shape, n_samples=3, method="lanczos", rank=rank,
                                    seed=5, return_info=True)
        assert samples.shape == (3, *shape)
        assert info.details["rank"] == rank
        kept.append(info.kept_trace_fraction)
    assert all(0 < k < 1 for k in kept)
    assert all(b > a for a, b in zip(kept, kept[1:])), kept
    # the draws carry only the kept variance: their mean square is below the full variance
    many = sample_grid(kernel, shape, n_samples=2000, method="lanczos", rank=2, seed=6)
    assert np.mean(many**2) < 10.0 * (kept[0] + 0.1)


def test_lanczos_figure_2_kernel_rank_100_keeps_less_than_the_trace():
    """Section 3.1: eq 18 with lambda = (500, 5), phi = pi/6 on 30 x 30 points; rank 100
    (GPyTorch's default max_root_decomposition_size) loses part of the variance."""
    kernel = RotatedExponentialKernel(10.0, (500.0, 5.0), PI / 6)
    _, info = sample_grid(kernel, (30, 30), method="lanczos", rank=100, seed=0, return_info=True)
    assert 0.5 < info.kept_trace_fraction < 1.0
    assert info.details["rank"] == 100


# --------------------------------------------------------------------------- seeds, shapes

ALL_METHODS = [("cholesky", {}), ("lanczos", {"rank": 8}), ("circulant", {})]


@pytest.mark.parametrize("method, kwargs", ALL_METHODS)
@pytest.mark.parametrize("shape", [(10,), (4, 5)])
def test_same_seed_same_array_different_seed_different(method, kwargs, shape):
    kernel = _exp1d(2.0) if len(shape) == 1 else _rot((2.0, 1.0))
    a = sample_grid(kernel, shape, n_samples=3, method=method, seed=123, **kwargs)
    b = sample_grid(kernel, shape, n_samples=3, method=method, seed=123, **kwargs)
    c = sample_grid(kernel, shape, n_samples=3, method=method, seed=124, **kwargs)
    assert a.shape == (3, *shape)
    np.testing.assert_array_equal(a, b)  # bitwise
    assert not np.allclose(a, c)
    # a Generator is accepted: default_rng(123) is the stream seed=123 stands for
    d = sample_grid(kernel, shape, n_samples=3, method=method,
                    seed=np.random.default_rng(123), **kwargs)
    np.testing.assert_array_equal(a, d)
    rng = np.random.default_rng(9)
    e = sample_grid(kernel, shape, n_samples=3, method=method, seed=rng, **kwargs)
    f = sample_grid(kernel, shape, n_samples=3, method=method, seed=rng, **kwargs)
    assert not np.allclose(e, f)  # the generator's state advances


@pytest.mark.parametrize("method", ["cholesky", "lanczos", "circulant", "auto"])
@pytest.mark.parametrize("shape", [(7,), (3, 5)])
@pytest.mark.parametrize("n_samples", [1, 2, 5])
def test_return_shape(method, shape, n_samples):
    kernel = _exp1d(2.0) if len(shape) == 1 else _rot((2.0, 1.0))
    out = sample_grid(kernel, shape, n_samples=n_samples, method=method, seed=0,
                      **({"rank": 4} if method == "lanczos" else {}))
    assert out.shape == (n_samples, *shape) and out.dtype == np.float64
    assert np.all(np.isfinite(out))


def test_scalar_shape_and_plain_function_kernel():
    out = sample_grid(lambda t: np.exp(-np.abs(t[..., 0]) / 2.0), 9, n_samples=2,
                      method="cholesky", seed=0)
    ref = sample_grid(_exp1d(2.0), (9,), n_samples=2, method="cholesky", seed=0)
    assert out.shape == (2, 9)
    np.testing.assert_allclose(out, ref, rtol=1e-12, atol=1e-12)


@pytest.mark.parametrize("method", ["cholesky", "circulant"])
def test_spacing_equals_rescaled_lengthscale_1d(method):
    """Lengthscale L at spacing d is lengthscale L / d at spacing 1 (same seed, same draw)."""
    a = sample_grid(_exp1d(3.0), (15,), spacing=0.5, n_samples=4, method=method, seed=31)
    b = sample_grid(_exp1d(6.0), (15,), spacing=1.0, n_samples=4, method=method, seed=31)
    np.testing.assert_allclose(a, b, rtol=1e-9, atol=1e-9)


@pytest.mark.parametrize("method", ["cholesky", "circulant"])
def test_spacing_equals_rescaled_lengthscales_2d_per_axis(method):
    """With angle 0, lengthscales (la, lb) act on (x, y): on spacing (dy, dx) they equal
    (la / dx, lb / dy) on spacing 1. Unequal dy, dx checks the order of both."""
    dy, dx = 2.0, 0.5
    a = sample_grid(_rot((3.0, 4.0), angle=0.0), (6, 7), spacing=(dy, dx), n_samples=3,
                    method=method, seed=32)
    b = sample_grid(_rot((3.0 / dx, 4.0 / dy), angle=0.0), (6, 7), spacing=1.0, n_samples=3,
                    method=method, seed=32)
    np.testing.assert_allclose(a, b, rtol=1e-9, atol=1e-9)
    c = sample_grid(_rot((3.0 / dy, 4.0 / dx), angle=0.0), (6, 7), spacing=1.0, n_samples=3,
                    method=method, seed=32)
    assert not np.allclose(a, c, rtol=1e-3, atol=1e-3)


# --------------------------------------------------------------------------- memory refusal

@pytest.mark.parametrize("method", ["cholesky", "lanczos"])
def test_dense_methods_refuse_before_allocating(monkeypatch, method):
    monkeypatch.setattr(grid_sampler, "_available_bytes", lambda: 2**30)

    def forbidden(*args, **kwargs):
        raise AssertionError("the covariance was built before the memory check")

    monkeypatch.setattr(grid_sampler, "grid_covariance", forbidden)
    start = time.perf_counter()
    with pytest.raises(ValueError, match="GiB") as excinfo:
        sample_grid(_rot((5.0, 5.0)), (400, 400), method=method, seed=0)
    assert time.perf_counter() - start < 2.0
    message = str(excinfo.value)
    assert "1.0 GiB" in message and "circulant" in message and method in message


def test_auto_avoids_cholesky_when_memory_is_short(monkeypatch):
    monkeypatch.setattr(grid_sampler, "_available_bytes", lambda: 2**20)  # 1 MiB: 20 x 20 won't fit
    method, reason = choose_method(_exp1d(2.0), (600,))
    assert method == "circulant" and "out of memory" in reason


# --------------------------------------------------------------------------- circulant embedding

def test_not_embeddable_error_reports_eigenvalue_and_tries():
    assert issubclass(circulant.NotEmbeddableError, ValueError)
    kernel = RotatedExponentialKernel(10.0, (500.0, 5.0), PI / 6)
    with pytest.raises(circulant.NotEmbeddableError) as excinfo:
        circulant.embed(kernel.acvf, (20, 20), max_points=10**5)
    message = str(excinfo.value)
    match = re.search(r"most negative (-[0-9.e+-]+) x r\(0\)", message)
    assert match, message
    assert float(match.group(1)) < -1e-10
    assert re.search(r"tried \[\(\d+, \d+\)", message), message
    assert "max_points = 100000" in message
    assert "approximate=True" in message


def test_sample_grid_propagates_not_embeddable_error(monkeypatch):
    kernel = RotatedExponentialKernel(10.0, (500.0, 5.0), PI / 6)
    original = circulant.embed
    monkeypatch.setattr(circulant, "embed",
                        lambda *a, **k: original(*a, **{**k, "max_points": 10**5}))
    with pytest.raises(ValueError, match="negative"):
        sample_grid(kernel, (20, 20), method="circulant", seed=0)


def _box(lags):
    """The rectangle 'ACVF' of the notation chapter: its PSD is a sinc, negative in places."""
    from roughgp.gp import acvf
    return acvf.rectangular(lags, variance=1.0, width=1.0)


@pytest.mark.parametrize("method", ["auto", "circulant", "cholesky", "lanczos"])
def test_non_positive_definite_acvf_is_refused(method):
    with pytest.raises(ValueError, match="not positive"):
        sample_grid(_box, (201,), spacing=0.05, method=method, seed=0)


def test_non_positive_definite_acvf_is_refused_on_the_first_torus():
    # not after growing the torus to max_points (minutes and GiBs: a CI timeout once)
    for truncation, first in (("none", 400), ("smooth", 405)):  # 2 (n - 1); 2 n - 1, fast
        with pytest.raises(circulant.NotEmbeddableError, match=rf"torus \({first},\)") as excinfo:
            circulant.embed(_box, (201,), spacing=0.05, truncation=truncation)
        assert "no larger torus" in str(excinfo.value)


# lambda_a = 100 instead of figure 2's 500 keeps the approximate torus small (about 1.2 M
# points instead of 35 M) while still needing clipping; exact embedding of figure 2's kernel
# at these max_points is what the test above shows failing.
APPROX_KERNEL = dict(variance=10.0, lengthscales=(100.0, 5.0), angle=PI / 6)


def test_approximate_embedding_clips_little():
    """The plain wrap (truncation="none") of this kernel needs clipping within 2^22 points; the
    smooth truncation embeds it exactly there."""
    kernel = RotatedExponentialKernel(**APPROX_KERNEL)
    with pytest.raises(circulant.NotEmbeddableError):
        circulant.embed(kernel.acvf, (20, 20), max_points=10**5, truncation="none")
    smooth = circulant.embed(kernel.acvf, (20, 20), max_points=2**22)
    assert smooth.exact and smooth.truncation == "smooth" and smooth.min_eigenvalue >= -1e-10
    emb = circulant.embed(kernel.acvf, (20, 20), approximate=True, max_points=2**22,
                          truncation="none")
    assert 0 < emb.clipped_fraction < 1e-4
    assert not emb.exact
    assert emb.min_eigenvalue < 0
    assert emb.grid_shape == (20, 20) and emb.scale.shape == emb.torus_shape
    assert all(m >= 2 * (20 - 1) for m in emb.torus_shape)
    assert len(emb.tries) >= 1 and emb.tries[-1][0] == emb.torus_shape


def test_sample_grid_approximate_warns_and_reports():
    kernel = RotatedExponentialKernel(**APPROX_KERNEL)
    with pytest.warns(UserWarning, match="clipped"):
        samples, info = sample_grid(kernel, (20, 20), n_samples=2, method="circulant",
                                    approximate=True, seed=1, return_info=True,
                                    truncation="none")
    assert samples.shape == (2, 20, 20) and np.all(np.isfinite(samples))
    assert 0 < info.clipped_fraction < 1e-4
    assert info.min_eigenvalue < 0 and info.torus_shape is not None


def test_exact_embedding_of_a_short_kernel_has_no_clipping_and_draws_warn_nothing():
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        _, info = sample_grid(_rot((3.0, 1.5)), (10, 12), method="circulant", seed=0,
                              return_info=True)
    assert info.clipped_fraction == 0.0 and info.min_eigenvalue >= -1e-10
    ty, tx = info.torus_shape
    assert ty >= 2 * (10 - 1) and tx >= 2 * (12 - 1)


def test_embedding_cache():
    kernel = _rot((2.7, 1.3), variance=1.1)
    _, first = sample_grid(kernel, (9, 8), method="circulant", seed=0, return_info=True)
    a, second = sample_grid(kernel, (9, 8), method="circulant", seed=0, return_info=True)
    assert second.cached is True
    assert second.torus_shape == first.torus_shape
    b, _ = sample_grid(kernel, (9, 8), method="circulant", seed=0, return_info=True)
    np.testing.assert_array_equal(a, b)
    kernel.lengthscales = (2.9, 1.3)  # a changed hyperparameter must not reuse the embedding
    c, third = sample_grid(kernel, (9, 8), method="circulant", seed=0, return_info=True)
    assert third.cached is False
    assert not np.allclose(a, c)
    kernel.variance = 4.4  # variance 4x: same draw, twice as large (no stale embedding)
    kernel.lengthscales = (2.7, 1.3)
    d, fourth = sample_grid(kernel, (9, 8), method="circulant", seed=0, return_info=True)
    assert fourth.cached is False
    np.testing.assert_allclose(d, 2.0 * a, rtol=1e-12, atol=1e-12)
    # another grid or spacing is another embedding
    _, other = sample_grid(kernel, (9, 8), spacing=0.5, method="circulant", seed=0,
                           return_info=True)
    assert other.cached is False


def test_embedding_cache_keeps_the_newest_within_its_count_and_byte_budget(monkeypatch):
    monkeypatch.setattr(grid_sampler, "_EMBEDDINGS", {})
    monkeypatch.setattr(grid_sampler, "_CACHE_SIZE", 3)
    kernels = [_rot((2.0 + 0.1 * i, 1.0)) for i in range(5)]
    for kernel in kernels:
        sample_grid(kernel, (9, 8), method="circulant", seed=0)
    assert len(grid_sampler._EMBEDDINGS) == 3
    _, newest = sample_grid(kernels[-1], (9, 8), method="circulant", seed=0, return_info=True)
    _, oldest = sample_grid(kernels[0], (9, 8), method="circulant", seed=0, return_info=True)
    assert newest.cached and not oldest.cached
    one = next(iter(grid_sampler._EMBEDDINGS.values())).nbytes
    monkeypatch.setattr(grid_sampler, "_CACHE_BYTES", 2 * one)
    sample_grid(kernels[1], (9, 8), method="circulant", seed=0)
    assert len(grid_sampler._EMBEDDINGS) == 2
    monkeypatch.setattr(grid_sampler, "_CACHE_BYTES", 0)  # the newest stays even over budget
    sample_grid(kernels[2], (9, 8), method="circulant", seed=0)
    assert len(grid_sampler._EMBEDDINGS) == 1


# --------------------------------------------------------------------------- additive kernel

def _additive():
    return AdditiveKernel(MaternKernel(0.5, lengthscale=3.0, variance=1.0),
                          MaternKernel(0.5, lengthscale=2.0, variance=0.5))


def _additive_wrong():
    return AdditiveKernel(MaternKernel(0.5, lengthscale=6.0, variance=1.0),
                          MaternKernel(0.5, lengthscale=4.0, variance=0.5))


def test_additive_kernel_draws_are_column_plus_row_profiles():
    shape = (7, 9)
    z, info = sample_grid(_additive(), shape, spacing=(0.5, 1.5), n_samples=3,
                          method="circulant", seed=3, return_info=True)
    assert z.shape == (3, *shape)
    assert info.details.get("additive") is True
    diff = z - z[:, :, :1]  # z[iy, ix] - z[iy, 0] = G_x(x) - G_x(0), independent of iy
    np.testing.assert_allclose(diff, np.broadcast_to(diff[:, :1, :], diff.shape),
                               rtol=0, atol=1e-12)
    diff_y = z - z[:, :1, :]  # ... and z[iy, ix] - z[0, ix] independent of ix
    np.testing.assert_allclose(diff_y, np.broadcast_to(diff_y[:, :, :1], diff_y.shape),
                               rtol=0, atol=1e-12)
    assert np.ptp(diff) > 0 and np.ptp(diff_y) > 0


def test_additive_kernel_sample_covariance_matches():
    shape, spacing = (5, 6), (1.0, 0.8)
    samples = sample_grid(_additive(), shape, spacing=spacing, n_samples=N_DRAWS,
                          method="circulant", seed=44)
    _assert_covariance_matches(samples, _additive(), _additive_wrong(), shape, spacing)


# --------------------------------------------------------------------------- choose_method

def _costs(reason):
    cholesky = re.search(r"Cholesky ~([0-9.e+-]+) s", reason)
    circ = re.search(r"circulant ~([0-9.e+-]+) s", reason)
    return (float(cholesky.group(1)) if cholesky else math.inf), float(circ.group(1))


def test_choose_method_small_short_range_grid_picks_cholesky_only_if_cheaper():
    method, reason = choose_method(_exp1d(3.0), (12,))
    assert method == "cholesky" and reason
    chol, circ = _costs(reason)
    assert chol <= circ


def test_choose_method_large_grid_picks_circulant(monkeypatch):
    kernel = MaternKernel(0.5, dim=2, lengthscale=5.0)
    method, reason = choose_method(kernel, (300, 300))
    assert method == "circulant" and reason
    # even with unlimited memory, N^3 for N = 90 000 is far costlier than FFTs
    monkeypatch.setattr(grid_sampler, "_available_bytes", lambda: 2**50)
    method, reason = choose_method(kernel, (300, 300))
    assert method == "circulant"
    chol, circ = _costs(reason)
    assert circ < chol < math.inf


def test_choose_method_additive_kernel_is_circulant():
    method, reason = choose_method(_additive(), (40, 40))
    assert method == "circulant" and "additive" in reason


@pytest.mark.parametrize("kernel, shape", [(_exp1d(3.0), (12,)), (_additive(), (6, 7)),
                                           (_rot((2.0, 1.0)), (16, 16))])
def test_auto_reports_a_chosen_method(kernel, shape):
    samples, info = sample_grid(kernel, shape, n_samples=2, seed=0, return_info=True)
    assert info.method in ("cholesky", "circulant")
    expected, reason = choose_method(kernel, shape, n_samples=2)
    assert info.method == expected and info.reason == reason and reason
    assert samples.shape == (2, *shape)


# --------------------------------------------------------------------------- argument errors

@pytest.mark.parametrize("kwargs, name", [
    (dict(method="svd"), "method"),
    (dict(method="Cholesky"), "method"),
    (dict(n_samples=0), "n_samples"),
    (dict(n_samples=-2), "n_samples"),
    (dict(n_samples=2.0), "n_samples"),
    (dict(dtype=np.int32), "dtype"),
    (dict(dtype=np.complex128), "dtype"),
    (dict(dtype=np.float16), "dtype"),
    (dict(seed=1.5), "seed"),
    (dict(seed="abc"), "seed"),
    (dict(seed=np.random.RandomState(0)), "seed"),
    (dict(method="lanczos", rank=0), "rank"),
    (dict(method="lanczos", rank=-1), "rank"),
    (dict(method="lanczos", rank=2.5), "rank"),
    (dict(method="lanczos", rank=13), "rank"),
])
def test_argument_errors_name_the_parameter(kwargs, name):
    with pytest.raises(ValueError, match=name):
        sample_grid(_exp1d(2.0), (12,), **kwargs)


@pytest.mark.parametrize("shape, name", [((0,), "shape"), ((2, 3, 4), "shape")])
def test_bad_shape_errors(shape, name):
    with pytest.raises(ValueError, match=name):
        sample_grid(_exp1d(2.0), shape)


def test_bad_spacing_and_kernel_errors():
    with pytest.raises(ValueError, match="spacing"):
        sample_grid(_exp1d(2.0), (12,), spacing=0.0)
    with pytest.raises(ValueError, match="kernel"):
        sample_grid(42, (12,))


def test_long_profile_embedding_evaluates_the_acvf_in_large_blocks():
    """A 1-D torus of millions of points is evaluated in blocks of about 2**20 points, not one
    call per point-row (which took minutes for a fitted spectral mixture)."""
    calls = []

    def acvf(lags):
        calls.append(lags.shape)
        return np.exp(-np.abs(lags[..., 0]) / 50.0)

    values = truncation.wrapped_acvf(acvf, (3_000_000,), (1.0,))
    assert len(calls) == 3 and values[0] == 1.0
    calls.clear()
    truncation.wrapped_acvf(lambda lags: acvf(lags), (600, 4000), (1.0, 1.0))
    assert len(calls) == 3  # 262 rows of 4000 points per block


def test_narrow_spectral_lines_of_a_fitted_profile_are_sampled_exactly():
    """Lines as narrow as fitting.MIN_LINE_WIDTH allows (the turned-profile fits) embed on a
    finite torus without a spurious not-positive-definite error."""
    from roughgp.inference import fitting
    n = 8192
    width = fitting.MIN_LINE_WIDTH / n
    kernel = SpectralMixtureKernel(3, dim=1, weights=[7.3, 0.7, 0.14],
                                   means=[[1 / 250.0], [1e-6], [2 / 250.0]],
                                   variances=[[width ** 2], [(70 / n) ** 2], [width ** 2]])
    z, info = sampling.sample_grid(kernel, (n,), n_samples=2, seed=1, method="circulant",
                                   return_info=True)
    assert z.shape == (2, n) and np.all(np.isfinite(z))
    assert info.clipped_fraction == 0.0 and info.torus_shape[0] < 100 * n


@pytest.mark.parametrize("shape", [(7,), (1, 5), (4, 1), (3, 5), (6, 6)])
def test_gathered_covariance_is_the_lag_table_read_through_covariance_index(shape):
    from roughgp.sampling.grid_sampler import _gathered, covariance_index

    table = np.random.default_rng(len(shape)).standard_normal(tuple(2 * n - 1 for n in shape))
    expected = table.reshape(-1)[covariance_index(shape)]
    np.testing.assert_array_equal(_gathered(table, shape), expected)
