"""Tests of roughgp.models.arma: exact ACVFs against closed forms and an independent spectral
integral, linear-process weights, seeded simulation, exact likelihoods, sampled GPs as ARMA."""

import math

import numpy as np
import pytest
from scipy.linalg import toeplitz
from scipy.stats import multivariate_normal

from roughgp.models import arma
from roughgp.models.arma import (
    acvf_from_weights,
    ar1_to_ou,
    arma_acvf,
    arma_log_likelihood,
    gp_log_likelihood,
    linear_process_weights,
    matern32_to_arma21,
    ou_to_ar1,
    simulate_arma,
    yule_walker,
)


def poly_from_roots(roots):
    """Coefficients [a_1..a_p] of eq 12 with phi(z) = prod (1 - z / root) (real if conjugate)."""
    poly = np.array([1.0 + 0j])
    for root in roots:
        poly = np.convolve(poly, [1.0, -1.0 / root])
    assert np.allclose(poly.imag, 0.0)
    return -poly.real[1:]


def random_roots(rng, count, rmin=1.3, rmax=3.0):
    """``count`` roots (conjugate pairs and reals) with moduli in [rmin, rmax]."""
    roots = []
    while len(roots) < count:
        modulus = rng.uniform(rmin, rmax)
        if count - len(roots) >= 2 and rng.random() < 0.6:
            angle = rng.uniform(0.1, math.pi - 0.1)
            roots += [modulus * np.exp(1j * angle), modulus * np.exp(-1j * angle)]
        else:
            roots.append(modulus * rng.choice([-1.0, 1.0]))
    return roots


def spectral_acvf(ar, ma, sigma2, nlags, m=2**16):
    """Independent ACVF: sigma2 |theta|^2 / |phi|^2 integrated over f in [-1/2, 1/2) by FFT
    (trapezoid rule on a smooth periodic integrand, exponentially accurate)."""
    phi = np.fft.fft(np.r_[1.0, -np.asarray(ar, float)], m)
    theta = np.fft.fft(np.r_[1.0, np.asarray(ma, float)], m)
    spectrum = sigma2 * np.abs(theta) ** 2 / np.abs(phi) ** 2
    return np.fft.ifft(spectrum).real[:nlags]


# ------------------------------------------------------------- closed forms

def test_ar1_closed_form():
    a, s2 = -0.7, 1.3
    h = np.arange(12)
    np.testing.assert_allclose(arma_acvf([a], [], s2, 12), s2 * a**h / (1 - a * a),
                               rtol=1e-13, atol=1e-15)


def test_ma1_closed_form():
    b, s2 = 0.6, 2.0
    np.testing.assert_allclose(arma_acvf([], [b], s2, 5),
                               [s2 * (1 + b * b), s2 * b, 0, 0, 0], rtol=1e-14, atol=1e-15)


def test_arma11_closed_form():
    a, b, s2 = 0.5, -0.3, 0.8
    r0 = s2 * (1 + 2 * a * b + b * b) / (1 - a * a)
    r1 = s2 * (1 + a * b) * (a + b) / (1 - a * a)
    expected = np.r_[r0, r1 * a ** np.arange(9)]
    np.testing.assert_allclose(arma_acvf([a], [b], s2, 10), expected, rtol=1e-13, atol=1e-15)


def test_ar2_complex_roots_closed_form():
    # phi(z) = (1 - z / z0)(1 - z / conj z0), z0 = R e^{i w}: a1 = 2 cos(w) / R, a2 = -1 / R^2
    big_r, w, s2 = 1.5, 0.9, 1.0
    a1, a2 = 2 * math.cos(w) / big_r, -1 / big_r**2
    r0 = s2 * (1 - a2) / ((1 + a2) * ((1 - a2) ** 2 - a1 * a1))
    expected = [r0, a1 * r0 / (1 - a2)]
    for _ in range(10):
        expected.append(a1 * expected[-1] + a2 * expected[-2])
    got = arma_acvf([a1, a2], [], s2, 12)
    np.testing.assert_allclose(got, expected, rtol=1e-12, atol=1e-15)
    assert np.any(got < 0)  # damped oscillation from the complex roots


# ----------------------------------------------- independent implementations

ORDERS = [(4, 4), (4, 0), (0, 4), (3, 2), (1, 1), (2, 3), (4, 1), (1, 4), (3, 3), (2, 2),
          (4, 3), (1, 0)]


@pytest.mark.parametrize("p, q", ORDERS)
def test_random_arma_matches_spectral_integral_and_weights(p, q):
    rng = np.random.default_rng(10 * p + q)
    ar = poly_from_roots(random_roots(rng, p)) if p else np.zeros(0)
    ma = poly_from_roots(random_roots(rng, q, 0.5, 3.0)) if q else np.zeros(0)
    ma = -ma  # theta(z) = 1 + sum b_j z^j
    s2 = rng.uniform(0.5, 2.0)
    got = arma_acvf(ar, ma, s2, 30)
    scale = got[0]
    np.testing.assert_allclose(got, spectral_acvf(ar, ma, s2, 30), rtol=0, atol=1e-10 * scale)
    truncated = acvf_from_weights(linear_process_weights(ar, ma, 2000), s2, 30)
    np.testing.assert_allclose(got, truncated, rtol=0, atol=1e-10 * scale)


def test_roots_clustered_near_unit_circle():
    # four roots of modulus ~1.05 in two nearly equal conjugate pairs: ill-conditioned; the
    # linear system of Brockwell & Davis' method 2 loses ~7e-10 here, the step-down ~1e-11
    ar = poly_from_roots(random_roots(np.random.default_rng(0), 4, 1.05, 1.07))
    got = arma_acvf(ar, [0.5, -0.2], 1.0, 40)
    reference = spectral_acvf(ar, [0.5, -0.2], 1.0, 40, m=2**20)
    np.testing.assert_allclose(got, reference, rtol=0, atol=1e-10 * got[0])


def test_nearly_unit_root_is_still_stationary():
    a = 1 - 1e-9
    assert arma_acvf([a], [], 1.0, 1)[0] == pytest.approx(1 / (1 - a * a), rel=1e-6)
    with pytest.raises(ValueError, match="burn_in"):
        simulate_arma([a], [], 1.0, 4, seed=0)


# ----------------------------------------------------- linear process weights

def test_weights_ar1_and_ma():
    np.testing.assert_allclose(linear_process_weights([0.8], [], 10), 0.8 ** np.arange(10),
                               rtol=1e-14)
    np.testing.assert_array_equal(linear_process_weights([], [0.5, -0.3], 6),
                                  [1, 0.5, -0.3, 0, 0, 0])
    np.testing.assert_allclose(acvf_from_weights([1, 0.5, -0.3], 2.0, 5),
                               arma_acvf([], [0.5, -0.3], 2.0, 5), rtol=1e-14, atol=1e-15)


def test_truncated_ma_infinity_converges():
    ar, ma, s2 = [0.9], [0.4], 1.0
    exact = arma_acvf(ar, ma, s2, 20)
    errors = [np.abs(acvf_from_weights(linear_process_weights(ar, ma, n), s2, 20) - exact).max()
              for n in (10, 50, 100, 400)]
    assert all(e1 > e2 for e1, e2 in zip(errors, errors[1:])), errors
    assert errors[-1] < 1e-12 * exact[0]


# ------------------------------------------------------------------ simulation

def test_simulation_is_seeded():
    args = ([0.6, -0.2], [0.3], 1.0, 50)
    x = simulate_arma(*args, n_samples=3, seed=7)
    assert x.shape == (3, 50) and x.dtype == np.float64
    np.testing.assert_array_equal(x, simulate_arma(*args, n_samples=3, seed=7))
    np.testing.assert_array_equal(x, simulate_arma(*args, n_samples=3,
                                                   seed=np.random.default_rng(7)))
    assert not np.array_equal(x, simulate_arma(*args, n_samples=3, seed=8))


def test_default_burn_in_is_minimal_and_below_tolerance():
    a = 0.9  # tail variance fraction after B steps is a^(2B)
    burn = arma._burn_in(np.array([a]), np.zeros(0))
    assert a ** (2 * burn) <= arma.BURN_IN_TOL**2 < a ** (2 * (burn - 1))
    assert arma._burn_in(np.zeros(0), np.array([0.5, 0.2])) == 3


def test_simulated_acvf_matches_exact():
    ar, ma, s2, n, draws, lags = [0.7, -0.3], [0.4], 1.5, 64, 2000, 6
    x = simulate_arma(ar, ma, s2, n, n_samples=draws, seed=1)
    per_draw = np.stack([(x[:, : n - h] * x[:, h:]).mean(axis=1) for h in range(lags)], axis=1)
    mean, se = per_draw.mean(axis=0), per_draw.std(axis=0, ddof=1) / math.sqrt(draws)
    exact = arma_acvf(ar, ma, s2, lags)
    assert np.all(np.abs(mean - exact) < 5 * se), (mean, exact, se)


def test_first_values_are_stationary():
    # without the burn-in the first value would have variance sigma2, not sigma2 / (1 - a^2)
    a, s2, draws = 0.95, 1.0, 4000
    x = simulate_arma([a], [], s2, 3, n_samples=draws, seed=2)
    var, exact = (x**2).mean(axis=0), s2 / (1 - a * a)
    se = (x**2).std(axis=0, ddof=1) / math.sqrt(draws)
    assert np.all(np.abs(var - exact) < 5 * se), (var, exact, se)


def test_explicit_burn_in_drops_the_start():
    ar, ma, s2, n, burn = [0.5], [0.2], 2.0, 8, 5
    noise = math.sqrt(s2) * np.random.default_rng(9).standard_normal((1, burn + n))
    expected = np.zeros_like(noise)
    for t in range(burn + n):  # eq 12 from a zero start
        expected[0, t] = noise[0, t] + (0.5 * expected[0, t - 1] + 0.2 * noise[0, t - 1]
                                        if t else 0.0)
    np.testing.assert_allclose(simulate_arma(ar, ma, s2, n, burn_in=burn, seed=9),
                               expected[:, burn:], rtol=1e-14)


# ------------------------------------------------------------------ likelihood

@pytest.mark.parametrize("ar, ma", [([0.6, -0.2], [0.3]), ([], [0.5, -0.4]), ([0.95], [])])
def test_likelihood_equals_dense_gaussian(ar, ma):
    s2, n = 0.7, 50
    z = simulate_arma(ar, ma, s2, n, seed=3)[0]
    cov = toeplitz(arma_acvf(ar, ma, s2, n))
    expected = multivariate_normal(mean=np.zeros(n), cov=cov).logpdf(z)
    assert abs(arma_log_likelihood(z, ar, ma, s2) - expected) < 1e-10


def test_ou_likelihood_equals_ar1_factorisation():
    variance, lengthscale, spacing, n = 2.0, 3.0, 0.5, 80
    ar, ma, s2 = ou_to_ar1(variance, lengthscale, spacing)
    z = simulate_arma(ar, ma, s2, n, seed=4)[0]
    a = ar[0]
    expected = (-0.5 * (math.log(2 * math.pi * variance) + z[0] ** 2 / variance)
                - 0.5 * np.sum(np.log(2 * math.pi * s2) + (z[1:] - a * z[:-1]) ** 2 / s2))
    kernel = variance * np.exp(-np.arange(n) * spacing / lengthscale)
    assert abs(gp_log_likelihood(z, kernel) - expected) < 1e-10
    assert abs(arma_log_likelihood(z, ar, ma, s2) - expected) < 1e-10


def test_matern32_likelihood_equals_arma21():
    variance, lengthscale, spacing, n = 1.0, 4.0, 1.0, 60
    ar, ma, s2 = matern32_to_arma21(variance, lengthscale, spacing)
    z = simulate_arma(ar, ma, s2, n, seed=5)[0]
    t = math.sqrt(3) * np.arange(n) * spacing / lengthscale
    kernel = variance * (1 + t) * np.exp(-t)
    assert abs(gp_log_likelihood(z, kernel) - arma_log_likelihood(z, ar, ma, s2)) < 1e-10


def test_likelihood_rejects_indefinite_acvf_and_short_acvf():
    with pytest.raises(ValueError, match="acvf_values"):
        gp_log_likelihood([0.1, 0.2, 0.3], [1.0, 1.2, 0.0])
    with pytest.raises(ValueError, match="acvf_values"):
        gp_log_likelihood([0.1, 0.2, 0.3], [1.0, 0.5])
    with pytest.raises(ValueError, match="z"):
        gp_log_likelihood([0.1, np.nan], [1.0, 0.5])


# -------------------------------------------------------------------- mappings

@pytest.mark.parametrize("variance, lengthscale, spacing",
                         [(1.0, 1.0, 1.0), (2.5, 3.0, 0.5), (0.3, 0.2, 1.0), (1.0, 50.0, 1.0)])
def test_ou_to_ar1_reproduces_exponential_kernel(variance, lengthscale, spacing):
    ar, ma, s2 = ou_to_ar1(variance, lengthscale, spacing)
    assert ma.size == 0
    k = np.arange(40)
    np.testing.assert_allclose(arma_acvf(ar, ma, s2, 40),
                               variance * np.exp(-k * spacing / lengthscale),
                               rtol=0, atol=1e-13 * variance)
    np.testing.assert_allclose(ar1_to_ou(ar[0], s2, spacing), (variance, lengthscale),
                               rtol=1e-12)


@pytest.mark.parametrize("variance, lengthscale, spacing",
                         [(1.0, 1.0, 1.0), (2.0, 3.0, 0.5), (0.7, 10.0, 1.0), (1.0, 0.3, 1.0),
                          (1.0, 1.0, 0.57), (1.0, 1.0, 0.58), (1.0, 1e-3, 1.0)])
def test_matern32_to_arma21_reproduces_kernel(variance, lengthscale, spacing):
    ar, ma, s2 = matern32_to_arma21(variance, lengthscale, spacing)
    rho = math.exp(-math.sqrt(3) * spacing / lengthscale)
    np.testing.assert_allclose(ar, [2 * rho, -rho * rho], rtol=1e-15)
    assert 0 <= ma[0] < 1 and s2 > 0  # invertible MA root (0: white noise, spacing >> lengthscale)
    t = math.sqrt(3) * np.arange(40) * spacing / lengthscale
    np.testing.assert_allclose(arma_acvf(ar, ma, s2, 40), variance * (1 + t) * np.exp(-t),
                               rtol=0, atol=1e-12 * variance)


def test_matern32_long_lengthscale():
    # lengthscale = 100 grid steps: double AR root at 1.0175, ill-conditioned (measured 4e-12)
    ar, ma, s2 = matern32_to_arma21(1.0, 100.0, 1.0)
    t = math.sqrt(3) * np.arange(300) / 100.0
    np.testing.assert_allclose(arma_acvf(ar, ma, s2, 300), (1 + t) * np.exp(-t),
                               rtol=0, atol=1e-10)


@pytest.mark.parametrize("spacing", [1e-2, 10.0, 100.0])
def test_matern32_small_spacing_ma_part(spacing):
    # c = sqrt(3) d / lambda <= 0.02: c0, c1 by their Taylor series (no cancellation), then
    # the invertible root of c1 b^2 - c0 b + c1 = 0
    c = math.sqrt(3) * spacing / 1e4
    rho2 = math.exp(-2 * c)
    c0 = 2 * rho2 * ((2 * c) ** 3 / 6 + (2 * c) ** 5 / 120 + (2 * c) ** 7 / 5040)
    c1 = 2 * rho2 * (c**3 / 3 + c**5 / 30 + c**7 / 840)
    b = min(np.roots([c1, -c0, c1]).real)
    _, ma, s2 = matern32_to_arma21(1.0, 1e4, spacing)
    assert ma[0] == pytest.approx(b, rel=1e-12) and s2 == pytest.approx(c1 / b, rel=1e-12)
    assert abs(ma[0] - (2 - math.sqrt(3))) < 1e-3  # the limit as spacing / lengthscale -> 0


@pytest.mark.parametrize("a", [0.0, -0.5, 1.0, 1.5, np.nan, [0.5, 0.5]])
def test_ar1_to_ou_rejects_a_outside_unit_interval(a):
    with pytest.raises(ValueError, match=r"^a must be in \(0, 1\)"):
        ar1_to_ou(a, 1.0, 1.0)


# ----------------------------------------------------------------- Yule-Walker

@pytest.mark.parametrize("p", [1, 2, 3, 4])
def test_yule_walker_recovers_ar(p):
    rng = np.random.default_rng(p)
    ar = poly_from_roots(random_roots(rng, p))
    fitted, s2 = yule_walker(arma_acvf(ar, [], 0.9, p + 5), p)
    np.testing.assert_allclose(fitted, ar, rtol=0, atol=1e-10)
    assert abs(s2 - 0.9) < 1e-10
    higher, s2_higher = yule_walker(arma_acvf(ar, [], 0.9, p + 5), p + 2)
    np.testing.assert_allclose(higher, np.r_[ar, 0, 0], rtol=0, atol=1e-10)


def test_yule_walker_order_range():
    r = arma_acvf([0.5], [], 1.0, 4)
    for p in (-1, 4, 1.5, True):
        with pytest.raises(ValueError, match=r"^p must"):
            yule_walker(r, p)
    assert yule_walker(r, 0)[1] == pytest.approx(r[0])


# ---------------------------------------------------------------------- errors

@pytest.mark.parametrize("ar", [[1.0], [1.2], [-1.0], list(poly_from_roots([0.8, 2.0])),
                                [2.0, -1.0]])
def test_nonstationary_ar_rejected(ar):
    with pytest.raises(ValueError, match=r"^ar must give a stationary") as info:
        arma_acvf(ar, [], 1.0, 5)
    assert "modulus" in str(info.value)
    with pytest.raises(ValueError, match=r"^ar "):
        simulate_arma(ar, [], 1.0, 5, seed=0)


@pytest.mark.parametrize("kwargs, name", [
    (dict(nlags=0), "nlags"), (dict(nlags=2.5), "nlags"), (dict(nlags=True), "nlags"),
    (dict(sigma2=0.0), "sigma2"), (dict(sigma2=-1.0), "sigma2"), (dict(sigma2=np.nan), "sigma2"),
    (dict(ar=[np.nan]), "ar"), (dict(ma=[np.inf]), "ma"), (dict(ar=[[0.1]]), "ar"),
    (dict(ar="abc"), "ar"), (dict(sigma2=[1.0, 2.0]), "sigma2"), (dict(sigma2="x"), "sigma2"),
])
def test_arma_acvf_input_errors(kwargs, name):
    args = dict(ar=[0.5], ma=[0.2], sigma2=1.0, nlags=5) | kwargs
    with pytest.raises(ValueError, match=rf"^{name} must"):
        arma_acvf(**args)


@pytest.mark.parametrize("kwargs, name", [
    (dict(seed=-1), "seed"), (dict(seed=1.5), "seed"), (dict(seed="abc"), "seed"),
    (dict(n_samples=0), "n_samples"), (dict(burn_in=-1), "burn_in"),
])
def test_simulate_input_errors(kwargs, name):
    with pytest.raises(ValueError, match=rf"^{name} must"):
        simulate_arma([0.5], [], 1.0, 10, **kwargs)


def test_mapping_input_errors():
    for bad in (0.0, -1.0, np.nan):
        for fn in (ou_to_ar1, matern32_to_arma21):
            with pytest.raises(ValueError, match=r"^lengthscale must"):
                fn(1.0, bad, 1.0)
            with pytest.raises(ValueError, match=r"^spacing must"):
                fn(1.0, 1.0, bad)
