"""Tests of roughgp.inference.posterior: priors, models, and the emcee posterior sampler."""

import math

import numpy as np
import pytest
from scipy import integrate, stats

from roughgp.gp import acvf as _acvf
from roughgp.inference import posterior
from roughgp.inference.posterior import (
    MAX_GRID_POINTS,
    LogNormal,
    LogUniform,
    Parameter,
    PosteriorModel,
    PosteriorSamples,
    ShortChainError,
    Uniform,
    UniformAngle,
    grid_likelihood,
    ground_patch_model,
    mcmc,
    profile_likelihood,
    sample_posterior,
    spectral_mixture_profile_model,
)
from roughgp.sampling import sample_grid

try:  # the dense Cholesky of a small patch: one BLAS thread (2-thread OpenBLAS on a loaded
    # 2-core machine can spin for 100 ms per 144 x 144 factorisation)
    from threadpoolctl import threadpool_limits
except ImportError:  # pragma: no cover
    import contextlib
    threadpool_limits = lambda *a, **k: contextlib.nullcontext()  # noqa: E731


@pytest.fixture
def one_blas_thread():
    with threadpool_limits(1, user_api="blas"):
        yield


def white_noise_model(z, low=1e-4, high=1e4):
    """Eq 11: z_i ~ N(0, sigma^2) iid, so the ACVF is sigma^2 at lag 0 and 0 elsewhere."""
    return PosteriorModel(
        (Parameter("variance", LogUniform(low, high)),),
        profile_likelihood(z, 1.0, lambda p, lags: p["variance"] * (lags == 0)))


@pytest.fixture(scope="module")
def white_noise():
    # short (n = 20), so that the prior's Jacobian moves the posterior by more than the
    # Monte-Carlo tolerance (see test_white_noise_posterior_is_inverse_gamma)
    z = np.random.default_rng(1).normal(0.0, 1.5, 20)
    return z, white_noise_model(z)


# ------------------------------------------------------------------ priors

@pytest.mark.parametrize("prior", [LogUniform(0.01, 30.0), LogNormal(0.3, 0.7),
                                   Uniform(-1.0, 2.5)])
def test_prior_density_in_u_integrates_to_one(prior):
    rng = np.random.default_rng(0)
    draws = prior.sample(rng, 20000)
    lo, hi = draws.min() - 3, draws.max() + 3
    # the support edges as break points so quad sees the jumps of the uniform densities
    points = [p for p in (getattr(prior, "low", None), getattr(prior, "high", None))
              if p is not None]
    points = [float(prior.to_unconstrained(p)) for p in points]
    total, err = integrate.quad(lambda u: math.exp(prior.logpdf(u)), lo, hi, points=points or None,
                                limit=200)
    assert total == pytest.approx(1.0, abs=1e-6)
    # the draws follow the density: compare the mean in u with the numerical mean
    mean, _ = integrate.quad(lambda u: u * math.exp(prior.logpdf(u)), lo, hi,
                             points=points or None, limit=200)
    assert np.mean(draws) == pytest.approx(mean, abs=5 * np.std(draws) / math.sqrt(draws.size))


def test_log_uniform_is_one_over_theta_in_natural_units():
    prior = LogUniform(0.5, 8.0)
    # p_theta(theta) = p_u(log theta) / theta must be 1 / (theta log(high / low))
    for theta in (0.6, 1.0, 7.9):
        p_theta = math.exp(prior.logpdf(math.log(theta))) / theta
        assert p_theta == pytest.approx(1.0 / (theta * math.log(16.0)))
    assert prior.logpdf(math.log(0.49)) == -np.inf
    assert prior.logpdf(math.log(8.1)) == -np.inf


def test_lognormal_matches_scipy_in_natural_units():
    prior = LogNormal(math.log(2.0), 0.4)
    theta = np.array([0.5, 2.0, 5.0])
    p_theta = np.exp(prior.logpdf(np.log(theta))) / theta  # Jacobian back to theta
    np.testing.assert_allclose(p_theta, stats.lognorm(s=0.4, scale=2.0).pdf(theta), rtol=1e-12)


def test_angle_wrapping_and_flat_density():
    prior = UniformAngle()  # period pi
    np.testing.assert_allclose(prior.wrap([0.1, math.pi + 0.1, -math.pi + 0.1, 3 * math.pi]),
                               [0.1, 0.1, 0.1, 0.0], atol=1e-12)
    assert prior.wrap(math.pi / 2) == pytest.approx(-math.pi / 2)  # [-p/2, p/2)
    # no boundary: the same density everywhere, 1 / period
    np.testing.assert_allclose(prior.logpdf([-10.0, 0.0, 1.5, 10.0]), -math.log(math.pi))
    draws = prior.sample(np.random.default_rng(0), 1000)
    assert np.all((draws >= -math.pi / 2) & (draws < math.pi / 2))
    assert UniformAngle(2 * math.pi).wrap(4.0) == pytest.approx(4.0 - 2 * math.pi)


def test_bad_priors_refused():
    with pytest.raises(ValueError, match="high must be > low"):
        LogUniform(2.0, 1.0)
    with pytest.raises(ValueError, match="low must be > 0"):
        LogUniform(0.0, 1.0)
    with pytest.raises(ValueError, match="sigma must be > 0"):
        LogNormal(0.0, -1.0)
    with pytest.raises(ValueError, match="prior of 'a'"):
        Parameter("a", object())
    with pytest.raises(ValueError, match="unique"):
        PosteriorModel((Parameter("a", Uniform(0, 1)), Parameter("a", Uniform(0, 1))),
                       lambda p: 0.0)


# ------------------------------------------------------------------ the conjugate case

def test_white_noise_posterior_is_inverse_gamma(white_noise):
    z, model = white_noise
    n, s = z.size, float(np.sum(z * z))
    # prior p(s2) ∝ 1/s2, likelihood ∝ s2^(-n/2) exp(-S / (2 s2)), so the posterior is
    # ∝ s2^(-n/2 - 1) exp(-(S/2) / s2): InvGamma(alpha = n/2, beta = S/2). The LogUniform
    # range [1e-4, 1e4] cuts off nothing (S/n ≈ 2, posterior sd in log ≈ sqrt(2/n) = 0.3).
    exact = stats.invgamma(n / 2, scale=s / 2)
    result = sample_posterior(model, n_walkers=12, n_steps=2500, seed=3)
    draws = result.samples["variance"]
    tau = result.autocorr_time["variance"]
    assert result.n_steps >= 50 * tau
    assert 0.3 < result.acceptance_fraction < 0.95

    # Monte-Carlo tolerance: the effective sample size is ESS = (walkers x kept steps) / tau.
    # A sample p-quantile has standard error sqrt(p (1 - p)) / (f(q_p) sqrt(ESS)), f the
    # posterior density at the quantile. Work in log s2 (nearly normal, sd sigma_u): the
    # median's error is 1.25 sigma_u / sqrt(ESS), the 2.5 % / 97.5 % quantiles' is
    # 2.67 sigma_u / sqrt(ESS). Allow 4 standard errors (the seed is fixed, so this is a
    # check of correctness, not a flaky probability), in relative terms on s2.
    ess = draws.size / tau
    sigma_u = float(np.std(np.log(exact.rvs(200000, random_state=0))))
    tol_median = 4 * 1.25 * sigma_u / math.sqrt(ess)
    tol_tail = 4 * 2.67 * sigma_u / math.sqrt(ess)
    assert tol_median < 0.07 and tol_tail < 0.15  # a few per cent: the check has teeth...
    summary = result.summary()["variance"]
    assert math.log(summary["median"] / exact.median()) == pytest.approx(0.0, abs=tol_median)
    assert math.log(summary["lo95"] / exact.ppf(0.025)) == pytest.approx(0.0, abs=tol_tail)
    assert math.log(summary["hi95"] / exact.ppf(0.975)) == pytest.approx(0.0, abs=tol_tail)
    assert result.interval("variance", 0.95) == (summary["lo95"], summary["hi95"])
    # ...so also check the whole shape: draws against the exact CDF (KS on each walker's
    # chain thinned by tau, so the draws are close to independent)
    step = max(1, int(math.ceil(tau)))
    thinned = np.exp(result.chain[:, result.burn_in::step, 0]).reshape(-1)
    assert stats.kstest(thinned, exact.cdf).pvalue > 1e-3
    # a prior flat in s2 (the Jacobian of u = log s2 forgotten) would give
    # InvGamma(n/2 - 1, S/2): its median is about 11 % higher, well beyond tol_median, so the
    # Jacobian is tested
    wrong = stats.invgamma(n / 2 - 1, scale=s / 2)
    assert abs(math.log(wrong.median() / exact.median())) > tol_median


def test_result_layout(white_noise):
    _, model = white_noise
    result = sample_posterior(model, n_walkers=4, n_steps=40, seed=0, burn_in=10, thin=2,
                              allow_short=True)
    assert isinstance(result, PosteriorSamples)
    assert result.chain.shape == (4, 40, 1)
    assert result.samples["variance"].shape == (4 * 15,)
    assert result.log_prob.shape == (4 * 15,)
    assert np.all(result.samples["variance"] > 0)
    np.testing.assert_allclose(np.log(result.samples["variance"]),
                               result.chain[:, 11::2, 0].T.reshape(-1))  # emcee's thinning
    assert set(result.summary()["variance"]) == {"median", "lo68", "hi68", "lo95", "hi95"}


# ------------------------------------------------------------------ seeding, short chains

def test_same_seed_same_samples(white_noise):
    _, model = white_noise
    kwargs = dict(n_walkers=4, n_steps=60, allow_short=True)
    a = sample_posterior(model, seed=11, **kwargs)
    b = sample_posterior(model, seed=11, **kwargs)
    c = sample_posterior(model, seed=12, **kwargs)
    np.testing.assert_array_equal(a.chain, b.chain)
    np.testing.assert_array_equal(a.samples["variance"], b.samples["variance"])
    assert not np.array_equal(a.chain, c.chain)
    # also from an initial point: the scatter and the moves are both seeded
    d = sample_posterior(model, seed=5, initial={"variance": 2.0}, **kwargs)
    e = sample_posterior(model, seed=5, initial={"variance": 2.0}, **kwargs)
    np.testing.assert_array_equal(d.chain, e.chain)
    np.testing.assert_allclose(d.chain[:, 0, 0], math.log(2.0), atol=1e-2)


def test_short_chain_refused_unless_allowed(white_noise):
    _, model = white_noise
    with pytest.raises(ShortChainError, match=r"n_steps = 60 .*autocorrelation time.*"
                                              r"needs n_steps >= \d+") as info:
        sample_posterior(model, n_walkers=4, n_steps=60, seed=0)
    assert isinstance(info.value, ValueError)
    result = sample_posterior(model, n_walkers=4, n_steps=60, seed=0, allow_short=True)
    assert 60 < 50 * result.autocorr_time["variance"]


def test_bad_arguments(white_noise):
    _, model = white_noise
    with pytest.raises(ValueError, match="n_walkers must be an integer >= 2"):
        sample_posterior(model, n_walkers=1, n_steps=10)
    with pytest.raises(ValueError, match="burn_in"):
        sample_posterior(model, n_steps=10, burn_in=10)
    with pytest.raises(ValueError, match="zero posterior density"):
        sample_posterior(model, n_steps=10, initial={"variance": 1e6})
    with pytest.raises(ValueError, match="missing"):
        sample_posterior(model, n_steps=10, initial={"sigma": 1.0})


# ------------------------------------------------------------------ log posterior

def test_log_posterior_never_nan(white_noise):
    z, model = white_noise
    assert math.isfinite(model.log_posterior(np.array([0.5])))
    assert model.log_posterior(np.array([20.0])) == -np.inf  # outside the LogUniform
    assert model.log_posterior(np.array([np.nan])) == -np.inf
    assert model.log_posterior(np.array([0.1, 0.2])) == -np.inf  # wrong length
    # a non-positive-definite ACVF (|r_1| > r_0) and an overflowing one give -inf, not NaN
    bad = PosteriorModel(
        (Parameter("variance", LogNormal(0.0, 10.0)),),
        profile_likelihood(z, 1.0, lambda p, lags: p["variance"] * np.where(lags < 2, 1, 0.0)))
    assert bad.log_posterior(np.array([0.0])) == -np.inf
    assert model.log_posterior(np.array([1e3])) == -np.inf
    free = PosteriorModel((Parameter("variance", LogNormal(0.0, 1.0)),), model.log_likelihood)
    assert free.log_posterior(np.array([800.0])) == -np.inf  # exp(800) = inf
    # a likelihood that returns NaN is read as -inf too
    nan = PosteriorModel((Parameter("a", Uniform(0, 1)),), lambda p: float("nan"))
    assert nan.log_posterior(np.array([0.5])) == -np.inf


def test_log_posterior_is_likelihood_plus_prior(white_noise):
    z, model = white_noise
    u = 0.7
    s2 = math.exp(u)
    loglik = float(np.sum(stats.norm(0, math.sqrt(s2)).logpdf(z)))
    assert model.log_posterior(np.array([u])) == pytest.approx(
        loglik - math.log(math.log(1e8)), rel=1e-10)


# ------------------------------------------------------------------ ground patch (eq 18)

TRUTH = {"variance": 1.0, "lambda_a": 3.0, "lambda_b": 1.0, "angle": math.pi / 6,
         "noise_variance": 0.01}


@pytest.fixture(scope="module")
def patch():
    acvf = lambda lags: _acvf.rotated_exponential(  # noqa: E731
        lags, TRUTH["variance"], np.array([TRUTH["lambda_a"], TRUTH["lambda_b"]]),
        TRUTH["angle"])
    z = sample_grid(acvf, (12, 12), spacing=1.0, method="cholesky", seed=4)
    z = np.asarray(z).reshape(12, 12)
    z = z + np.random.default_rng(5).normal(0, math.sqrt(TRUTH["noise_variance"]), z.shape)
    return z


def test_ground_patch_log_posterior(patch, one_blas_thread):
    model = ground_patch_model(patch, 1.0)
    assert model.names == ["variance", "lambda_a", "lambda_b", "angle", "noise_variance"]
    u = model.to_unconstrained(TRUTH)
    assert math.isfinite(model.log_posterior(u))
    # the likelihood is the dense Gaussian density of the mean-removed patch
    from roughgp.sampling import grid_covariance
    cov = grid_covariance(lambda lags: _acvf.rotated_exponential(
        lags, 1.0, np.array([3.0, 1.0]), math.pi / 6), (12, 12), 1.0) + 0.01 * np.eye(144)
    y = (patch - patch.mean()).reshape(-1)
    expected = stats.multivariate_normal(np.zeros(144), cov).logpdf(y)
    assert model.log_likelihood(TRUTH) == pytest.approx(expected, rel=1e-10)
    # the angle has period pi: shifting by pi changes nothing
    shifted = u.copy()
    shifted[3] += math.pi
    assert model.log_posterior(shifted) == pytest.approx(model.log_posterior(u), rel=1e-10)
    # outside the prior's support (a lengthscale of 1e-3 < spacing / 10): -inf
    for name, value in (("lambda_a", 1e-3), ("variance", 1e3), ("noise_variance", 1e-12)):
        outside = model.to_unconstrained({**TRUTH, name: value})
        assert model.log_posterior(outside) == -np.inf
    # noise 0 with a tiny correlation length is still positive definite; a custom prior
    # that allows a negative-definite state is caught by the likelihood's ValueError
    custom = ground_patch_model(patch, 1.0, priors={"lambda_a": LogUniform(1.0, 5.0)})
    assert custom.parameters[1].prior == LogUniform(1.0, 5.0)
    with pytest.raises(ValueError, match="unknown names"):
        ground_patch_model(patch, 1.0, priors={"phi": UniformAngle()})


def test_grid_likelihood_non_pd_is_minus_inf(patch, one_blas_thread):
    # an "ACVF" that is not positive definite (a negative variance at lag 0): -inf, not NaN
    lik = grid_likelihood(patch - patch.mean(), 1.0,
                          lambda p: (lambda lags: -p["a"] * np.ones(lags.shape[:-1])))
    model = PosteriorModel((Parameter("a", LogUniform(0.1, 10.0)),), lik)
    assert model.log_posterior(np.array([0.0])) == -np.inf


def test_grid_refuses_large_patches():
    z = np.zeros((65, 64))  # 4160 points
    with pytest.raises(ValueError, match=rf"4160 points .*at most MAX_GRID_POINTS = "
                                         rf"{MAX_GRID_POINTS}"):
        ground_patch_model(z, 1.0)
    with pytest.raises(ValueError, match="4160 points"):
        grid_likelihood(z, 1.0, lambda p: None)


def test_ground_patch_short_run_wraps_angles(patch, one_blas_thread):
    model = ground_patch_model(patch, 1.0)
    result = sample_posterior(model, n_walkers=12, n_steps=40, seed=0, initial=TRUTH,
                              allow_short=True)
    angle = result.samples["angle"]
    assert np.all((angle >= -math.pi / 2) & (angle < math.pi / 2))
    lo, hi = result.interval("angle", 0.68)
    assert lo <= result.summary()["angle"]["median"] <= hi
    assert np.all(result.samples["lambda_a"] > 0)
    assert np.all(np.isfinite(result.log_prob))


def test_angle_summary_not_split_at_the_wrap():
    # a posterior concentrated at phi = pi/2 (the wrap point): samples come out on both ends,
    # the interval is still a short one around pi/2
    centre = math.pi / 2
    model = PosteriorModel((Parameter("angle", UniformAngle()),),
                           lambda p: -0.5 * (math.sin(p["angle"] - centre) / 0.05) ** 2)
    result = sample_posterior(model, n_walkers=8, n_steps=200, seed=1,
                              initial={"angle": centre}, allow_short=True)
    angle = result.samples["angle"]
    assert angle.min() < -1.3 and angle.max() > 1.3  # split by the wrapping
    lo, hi = result.interval("angle", 0.95)
    assert hi - lo < 0.5
    assert abs(UniformAngle().wrap(result.summary()["angle"]["median"] - centre)) < 0.05


# ------------------------------------------------------------------ spectral mixture profile

def test_spectral_mixture_profile_model():
    from roughgp.inference.fitting import spectral_mixture_log_likelihood
    rng = np.random.default_rng(2)
    x = np.arange(64) * 0.5
    z = np.sin(2 * math.pi * x / 4.0) + 0.3 * rng.normal(size=x.size)
    model = spectral_mixture_profile_model(x, z, 2)
    assert model.names == ["w_1", "mu_1", "v_1", "w_2", "mu_2", "v_2", "noise_variance"]
    assert model.initial is None
    params = {"w_1": 0.5, "mu_1": 0.25, "v_1": 0.01, "w_2": 0.1, "mu_2": 0.0, "v_2": 0.05,
              "noise_variance": 0.09}
    expected = spectral_mixture_log_likelihood(x, z - z.mean(), [0.5, 0.1], [0.25, 0.0],
                                               [0.01, 0.05], 0.09)
    assert model.log_likelihood(params) == pytest.approx(expected, rel=1e-10)
    assert math.isfinite(model.log_posterior(model.to_unconstrained(params)))
    # mu beyond the Nyquist frequency (1 / (2 * 0.5) = 1) is outside the prior
    assert model.log_posterior(model.to_unconstrained({**params, "mu_1": 1.2})) == -np.inf


def test_order_lengthscales_maps_the_mirrored_mode_onto_the_same_acvf():
    from roughgp.gp import acvf as acvf_module
    samples = {"lambda_a": np.array([1.0, 5.0]), "lambda_b": np.array([4.0, 2.0]),
               "angle": np.array([0.3, -0.2]), "variance": np.array([2.0, 3.0])}
    ordered = posterior.order_lengthscales(samples)
    assert np.all(ordered["lambda_a"] >= ordered["lambda_b"])
    assert ordered["lambda_a"][0] == 4.0 and ordered["lambda_b"][0] == 1.0
    assert ordered["angle"][0] == pytest.approx(0.3 + math.pi / 2 - math.pi)  # wrapped
    assert ordered["angle"][1] == pytest.approx(-0.2, abs=1e-15)
    assert np.array_equal(ordered["variance"], samples["variance"])
    assert samples["lambda_a"][0] == 1.0  # the input is not modified
    lags = np.random.default_rng(0).normal(size=(50, 2))
    for k in range(2):
        before = acvf_module.rotated_exponential(lags, 1.0, np.array(
            [samples["lambda_a"][k], samples["lambda_b"][k]]), samples["angle"][k])
        after = acvf_module.rotated_exponential(lags, 1.0, np.array(
            [ordered["lambda_a"][k], ordered["lambda_b"][k]]), ordered["angle"][k])
        assert np.allclose(before, after)
    with pytest.raises(ValueError, match="angle"):
        posterior.order_lengthscales({"lambda_a": [1.0], "lambda_b": [2.0]})


def test_maximum_a_posteriori_of_white_noise_is_the_analytic_mode():
    # eq 11 with a log-uniform prior: posterior of s2 is InvGamma(n/2, S/2); in u = log s2 the
    # density is InvGamma(s2) * s2, whose mode is at s2 = S / n
    z = np.random.default_rng(3).standard_normal(40) * 1.7
    model = posterior.PosteriorModel(
        (posterior.Parameter("noise_variance", posterior.LogUniform(1e-4, 1e4)),),
        posterior.profile_likelihood(z, 1.0, lambda p, lags: np.zeros(lags.shape)))
    mode = posterior.maximum_a_posteriori(model, {"noise_variance": 1.0})
    assert mode["noise_variance"] == pytest.approx(np.sum(z * z) / z.size, rel=1e-4)
    with pytest.raises(ValueError, match="initial"):
        posterior.maximum_a_posteriori(model, {"noise_variance": 1e6})


def _two_mode_result(n_walkers=6, n_steps=400, stray=2, seed=0):
    """A hand-made chain: every walker draws N(0, 1) around 0 (log posterior -x^2/2)
    except walker ``stray``, stuck around 10 (log posterior 50 lower)."""
    rng = np.random.default_rng(seed)
    chain = rng.standard_normal((n_walkers, n_steps, 1))
    chain[stray] += 10.0
    log_prob = -0.5 * chain[:, :, 0] ** 2
    log_prob[stray] -= 50.0
    params = (Parameter("a", Uniform(-100.0, 100.0)),)
    return mcmc._collect(params, chain, log_prob, np.full(n_walkers, 0.5),
                              tuple(range(n_walkers)), 100, 1, 50, True)


def test_main_mode_drops_the_stranded_walker():
    result = _two_mode_result()
    assert result.walker_log_prob.shape == (6, 400)
    assert np.mean(result.samples["a"]) > 1.0                    # the stray pulls the mean
    main = posterior.main_mode(result)
    assert main.walkers == (0, 1, 3, 4, 5)
    assert main.samples["a"].shape == (5 * 300,)
    assert abs(np.mean(main.samples["a"])) < 0.1                 # N(0, 1): 1500 draws
    assert main.chain.shape == (5, 400, 1)
    assert main.autocorr_time["a"] < 3                           # independent draws
    # a loose threshold keeps every walker
    assert posterior.main_mode(result, max_drop=1000.0).walkers == tuple(range(6))


def test_main_mode_checks_its_arguments_and_the_chain_length():
    result = _two_mode_result()
    with pytest.raises(ValueError, match="max_drop"):
        posterior.main_mode(result, max_drop=0.0)
    with pytest.raises(ValueError, match="result must be a PosteriorSamples"):
        posterior.main_mode({"a": np.zeros(3)})
    with pytest.raises(ShortChainError, match="n_steps >= "):
        posterior.main_mode(result, min_tau_multiple=1000)
    lonely = _two_mode_result(n_walkers=2, stray=1)
    with pytest.raises(ValueError, match="only 1 walker"):
        posterior.main_mode(lonely)


def test_main_mode_of_a_real_chain_keeps_samples_consistent(white_noise):
    _, model = white_noise
    result = sample_posterior(model, n_walkers=4, n_steps=60, seed=1, burn_in=20, thin=2,
                              allow_short=True)
    same = posterior.main_mode(result, max_drop=1e9, allow_short=True)
    np.testing.assert_array_equal(same.samples["variance"], result.samples["variance"])
    np.testing.assert_array_equal(same.log_prob, result.log_prob)
    assert same.autocorr_time == pytest.approx(result.autocorr_time)
    assert same.acceptance_fraction == pytest.approx(result.acceptance_fraction)
