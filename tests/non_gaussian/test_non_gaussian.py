"""Tests of roughgp.non_gaussian: the Johnson fit, the correlation map g and the surfaces."""

import math
import warnings

import numpy as np
import pytest

from roughgp import non_gaussian as ng
from roughgp.gp.kernels import MaternKernel
from roughgp.metrology import spectral, texture_heights

# (skewness, kurtosis, family): both sides of the lognormal line, both signs, symmetric cases
PAIRS = [(-1.5, 6.0, "SB"), (0.61, 2.13, "SB"), (3.0, 10.5, "SB"), (0.0, 2.0, "SB"),
         (0.5, 5.0, "SU"), (2.0, 20.0, "SU"), (-0.3, 3.2, "SU"), (0.0, 10.0, "SU")]


@pytest.fixture(scope="module")
def plateau():
    """The chapter's plateau-like target, Ssk = -1.5, Sku = 6 (a Johnson SB)."""
    johnson = ng.johnson_for(-1.5, 6.0)
    return johnson, ng.correlation_map(johnson)


# ------------------------------------------------------------------------ the Johnson fit


@pytest.mark.parametrize("skewness, kurtosis, family", PAIRS)
def test_johnson_moments_match_targets(skewness, kurtosis, family):
    johnson = ng.johnson_for(skewness, kurtosis, variance=2.5)
    assert johnson.family == family
    own = johnson.moments()
    assert own == pytest.approx((0.0, 2.5, skewness, kurtosis), abs=1e-9)
    # scipy's johnsonsu / johnsonsb (kurtosis there is the excess)
    mean, var, skew, excess = (float(v) for v in johnson.scipy().stats("mvsk"))
    assert abs(mean) < 1e-6 and var == pytest.approx(2.5, abs=1e-6)
    assert skew == pytest.approx(skewness, abs=1e-6)
    assert excess + 3 == pytest.approx(kurtosis, abs=1e-6)


def test_lognormal_line_and_normal():
    k_line, w = ng.lognormal_kurtosis(1.5)
    assert (w + 2) ** 2 * (w - 1) == pytest.approx(2.25, rel=1e-14)
    for s in (1.5, -1.5):
        johnson = ng.johnson_for(s, k_line)
        assert johnson.family == "SL" and (johnson.lam < 0) == (s < 0)
        assert johnson.moments() == pytest.approx((0.0, 1.0, s, k_line), abs=1e-9)
    assert ng.johnson_for(0.0, 3.0).family == "SN"
    # just above and below the line: SU and SB, still exact
    assert ng.johnson_for(1.5, k_line + 1e-3).family == "SU"
    assert ng.johnson_for(1.5, k_line - 1e-3).family == "SB"
    for k in (k_line + 1e-3, k_line - 1e-3):
        assert ng.johnson_for(1.5, k).moments().kurtosis == pytest.approx(k, abs=1e-9)


@pytest.mark.parametrize("skewness, kurtosis", [(1.0, 2.0), (2.0, 4.0), (0.0, 0.5),
                                                (-1.5, 3.0)])
def test_impossible_pairs_refused(skewness, kurtosis):
    with pytest.raises(ValueError, match=r"skewness\*\*2 \+ 1") as err:
        ng.johnson_for(skewness, kurtosis)
    assert "kurtosis" in str(err.value) and "allowed region" in str(err.value)


@pytest.mark.parametrize("kwargs, match", [
    (dict(skewness=math.nan, kurtosis=4.0), "skewness must be finite"),
    (dict(skewness=0.0, kurtosis=math.inf), "kurtosis must be finite"),
    (dict(skewness=0.0, kurtosis=4.0, variance=0.0), "variance must be > 0"),
    (dict(skewness="1", kurtosis=4.0), "skewness must be a real number"),
    (dict(skewness=0.1, kurtosis=1.02), "too close to the boundary"),
])
def test_bad_targets_refused(kwargs, match):
    with pytest.raises(ValueError, match=match):
        ng.johnson_for(**kwargs)


def test_transform_inverse_and_density(plateau):
    johnson, _ = plateau
    x = np.linspace(-4, 4, 41)
    z = johnson.transform(x)
    assert np.all(np.diff(z) > 0)
    assert np.allclose(johnson.inverse(z), x, atol=1e-9)
    lo, hi = johnson.support                     # SB: bounded, the plateau is the top bound
    assert lo < z.min() and z.max() < hi and hi - 0 < 1.5
    grid = np.linspace(lo, hi, 200001)
    pdf = johnson.pdf(grid)
    assert np.all(np.isfinite(pdf)) and np.trapezoid(pdf, grid) == pytest.approx(1, abs=1e-6)
    assert np.allclose(pdf[::5000], johnson.scipy().pdf(grid[::5000]), rtol=1e-9, atol=1e-12)


# ------------------------------------------------------------------- the correlation map


def test_correlation_map_basic_properties(plateau):
    _, g = plateau
    assert g(0.0) == 0.0
    assert g(1.0) == pytest.approx(1.0, abs=1e-14)
    rho = np.linspace(-1, 1, 2001)
    assert np.all(np.diff(g(rho)) > 0) and np.all(g.derivative(rho) > 0)
    assert np.all(g.coefficients >= 0) and g.coefficients.sum() == pytest.approx(1.0, abs=1e-14)
    assert abs(1 - g.captured) < 1e-10                      # the expansion holds the variance
    assert -1 < g.lower < -0.5                               # the attainable range [g(-1), 1]
    assert np.all(g(rho[rho > 0]) <= rho[rho > 0])           # without pre-distortion: too short


def test_correlation_map_matches_monte_carlo(plateau):
    johnson, g = plateau
    rng = np.random.default_rng(0)
    n = 400_000
    x1 = rng.standard_normal(n)
    e = rng.standard_normal(n)
    for rho in (-0.9, -0.4, 0.3, 0.7, 0.95):
        x2 = rho * x1 + math.sqrt(1 - rho**2) * e
        product = johnson.transform(x1) * johnson.transform(x2)   # mean 0, variance 1
        estimate, se = product.mean(), product.std(ddof=1) / math.sqrt(n)
        assert abs(g(rho) - estimate) < 4 * se, (rho, g(rho), estimate, se)


def test_su_hermite_coefficients_closed_form():
    """For SU, E[T(X) h_k(X)] is known in closed form: the quadrature must reproduce it."""
    johnson = ng.johnson_for(0.5, 5.0)
    g = ng.correlation_map(johnson, n_terms=25)
    b, omega = 1 / johnson.delta, johnson.gamma / johnson.delta
    exact = np.array([0.5 * johnson.lam * math.exp(b * b / 2)
                      * (math.exp(-omega) * b**k - math.exp(omega) * (-b) ** k)
                      / math.sqrt(math.factorial(k)) for k in range(1, 26)]) ** 2
    assert np.allclose(g.coefficients, exact / exact.sum(), rtol=1e-10, atol=1e-16)


def test_inverse_round_trip(plateau):
    _, g = plateau
    rho_x = np.linspace(-1, 1, 1001)
    assert np.allclose(g.inverse(g(rho_x)), rho_x, atol=1e-10)
    rho_z = np.linspace(g.lower, 1, 1001)
    assert np.allclose(g(g.inverse(rho_z)), rho_z, atol=1e-13)
    with pytest.raises(ValueError, match=r"not attainable.*\[g\(-1\), 1\]"):
        g.inverse(np.array([0.5, g.lower - 0.05]))
    assert g.inverse(np.array([g.lower - 0.05]), unattainable="clip")[0] == -1.0
    with pytest.raises(ValueError, match="rho_z must be a correlation <= 1"):
        g.inverse(1.1)
    with pytest.raises(ValueError, match="rho_z must be finite"):
        g.inverse(np.array([0.2, np.nan]))


def test_predistort_array_and_callable(plateau):
    johnson, g = plateau
    kernel = MaternKernel(nu=0.5, dim=1, variance=4.0, lengthscale=3.0)
    lags = np.arange(0, 20.0)[:, None]
    values = kernel.acvf(lags)
    rho_x = ng.predistort(values, johnson)
    assert rho_x[0] == pytest.approx(1.0) and np.all(rho_x[1:] > values[1:] / 4)
    assert np.allclose(g(rho_x), values / 4, atol=1e-13)
    func = ng.predistort(kernel, g)
    assert np.allclose(func(lags), rho_x, atol=1e-13)
    with pytest.raises(ValueError, match="not attainable"):
        ng.predistort(np.array([1.0, -0.9]), g)
    with pytest.raises(ValueError, match="exceeds variance"):
        ng.predistort(np.array([1.0, 0.5]), g, variance=0.5)


# ------------------------------------------------------------------------- the surfaces


@pytest.fixture(scope="module")
def surfaces_512():
    """16 surfaces of 512 x 512 (exponential ACVF, lengthscale 8), with and without
    pre-distortion, from the same seeds."""
    kernel = MaternKernel(nu=0.5, dim=2, variance=1.0, lengthscale=8.0)
    common = dict(skewness=-1.5, kurtosis=6.0, seed=2024, n_samples=16)
    with_, info = ng.non_gaussian_surface(kernel, (512, 512), **common)
    without, info_without = ng.non_gaussian_surface(kernel, (512, 512), predistortion=False,
                                                    **common)
    return kernel, with_, info, without, info_without


def test_surface_reaches_target_moments(surfaces_512):
    _, z, info, _, _ = surfaces_512
    assert z.shape == (16, 512, 512) and info.clipped_fraction == 0.0   # exact embedding
    params = [texture_heights.height_parameters(s) for s in z]
    for key, target in (("Ssk", -1.5), ("Sku", 6.0), ("Sq", 1.0)):
        values = np.array([p[key] for p in params])
        se = values.std(ddof=1) / math.sqrt(len(values))              # spread from the seeds
        assert abs(values.mean() - target) < 3 * se, (key, values.mean(), se)


def test_surface_acvf_better_with_predistortion(surfaces_512):
    kernel, z, info, z_without, _ = surfaces_512

    def mean_acvf(draws):
        return np.mean([spectral.empirical_acvf(s, max_lag=16, unbiased=True)[1]
                        for s in draws], axis=0)

    lags = spectral.empirical_acvf(z[0], max_lag=16)[0]
    target = kernel.acvf(lags)
    error_with = np.sqrt(np.mean((mean_acvf(z) - target) ** 2))
    estimate_without = mean_acvf(z_without)
    error_without = np.sqrt(np.mean((estimate_without - target) ** 2))
    # without pre-distortion the ACVF is r(0) g(rho), as predicted
    predicted_without = info.correlation_map(target)
    assert np.sqrt(np.mean((estimate_without - predicted_without) ** 2)) < error_without
    assert error_with < 0.5 * error_without, (error_with, error_without)


def test_surface_deterministic_by_seed():
    kernel = MaternKernel(nu=1.5, dim=2, variance=2.0, lengthscale=4.0)
    kwargs = dict(skewness=0.61, kurtosis=2.13)
    a, info = ng.non_gaussian_surface(kernel, (48, 40), seed=5, **kwargs)
    b, _ = ng.non_gaussian_surface(kernel, (48, 40), seed=5, **kwargs)
    c, _ = ng.non_gaussian_surface(kernel, (48, 40), seed=6, **kwargs)
    assert a.shape == (48, 40) and np.array_equal(a, b) and not np.allclose(a, c)
    assert info.variance == pytest.approx(2.0) and info.johnson.family == "SB"
    d, _ = ng.non_gaussian_surface(kernel, (48, 40), seed=5, method="cholesky", **kwargs)
    assert d.shape == (48, 40) and np.all(np.isfinite(d))


def test_surface_errors_and_limits():
    kernel = MaternKernel(nu=0.5, dim=1, variance=1.0, lengthscale=5.0)
    with pytest.raises(ValueError, match=r"skewness\*\*2 \+ 1"):
        ng.non_gaussian_surface(kernel, (256,), skewness=2.0, kurtosis=4.0, seed=0)

    def periodic(lags):          # a damped cosine: correlations down to -0.98, below g(-1)
        t = np.abs(lags[..., 0])
        return np.cos(2 * np.pi * t / 32) * np.exp(-t / 1000)

    with pytest.raises(ValueError, match=r"not positive definite.*below g\(-1\)"):
        ng.non_gaussian_surface(periodic, (2048,), skewness=-1.5, kurtosis=6.0, seed=0)

    # the squared exponential: its pre-distorted ACVF is not positive definite; the draw clips
    # the negative eigenvalues and says so
    smooth = MaternKernel(nu=math.inf, dim=1, variance=1.0, lengthscale=8.0)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        z, info = ng.non_gaussian_surface(smooth, (4096,), skewness=-1.5, kurtosis=6.0, seed=0)
    assert 0 < info.clipped_fraction < 0.01 and np.all(np.isfinite(z))
    assert any("not non-negative definite" in str(w.message) for w in caught)
    with pytest.raises(ValueError, match="max_clipped_fraction"):
        ng.non_gaussian_surface(smooth, (4096,), skewness=-1.5, kurtosis=6.0, seed=0,
                                max_clipped_fraction=1e-6)


def test_a_second_draw_of_one_kernel_reuses_its_embedding(monkeypatch):
    """A check draws 19-99 surfaces from one Johnson model: the pre-distorted ACVF's embedding
    is searched once (it took 22 s of a 24 s draw on a 256 x 128 field), the draws and the
    reported figures are those of a fresh search, and another kernel state or map is not
    served the cached one."""
    from roughgp.non_gaussian import draws
    from roughgp.sampling import grid_sampler
    monkeypatch.setattr(grid_sampler, "_EMBEDDINGS", {})
    monkeypatch.setattr(draws, "_INPUTS", {})
    kernel = MaternKernel(nu=1.5, dim=2, variance=2.0, lengthscale=4.0)
    first, info = ng.non_gaussian_surface(kernel, (48, 40), skewness=1.0, kurtosis=6.0, seed=3)
    again, cached = ng.non_gaussian_surface(kernel, (48, 40), skewness=1.0, kurtosis=6.0,
                                            seed=3)
    assert not info.sampling.cached and cached.sampling.cached
    np.testing.assert_array_equal(first, again)
    assert cached.unattainable_fraction == info.unattainable_fraction
    assert cached.sampling.torus_shape == info.sampling.torus_shape
    other, _ = ng.non_gaussian_surface(kernel, (48, 40), skewness=1.0, kurtosis=6.0, seed=4)
    assert not np.array_equal(first, other)
    _, new_map = ng.non_gaussian_surface(kernel, (48, 40), skewness=1.0, kurtosis=8.0, seed=3)
    longer = MaternKernel(nu=1.5, dim=2, variance=2.0, lengthscale=6.0)
    _, new_kernel = ng.non_gaussian_surface(longer, (48, 40), skewness=1.0, kurtosis=6.0,
                                            seed=3)
    assert not new_map.sampling.cached and not new_kernel.sampling.cached

    def plain(lags):  # a function of lags: nothing tells whether it changed, so not cached
        return kernel.acvf(lags)

    for _ in range(2):
        _, fresh = ng.non_gaussian_surface(plain, (48, 40), skewness=1.0, kurtosis=6.0, seed=3)
        assert not fresh.sampling.cached
