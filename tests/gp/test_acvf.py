"""Tests of roughgp.gp.acvf: values, symmetry, positive semi-definiteness, PSDs, torch/NumPy
agreement and input checks (Jawaid & Seewig, section 2.1, eq 5, 18, 21, 22)."""

from __future__ import annotations

import math

import numpy as np
import pytest
import torch
from scipy import integrate, special

from roughgp.gp import acvf as A

PI = math.pi


# --------------------------------------------------------------------------- fixtures / helpers

def _points(n, dim, seed=0, size=10.0):
    return np.random.default_rng(seed).uniform(0.0, size, size=(n, dim))


def _random_lags(n, dim, seed=1, scale=5.0):
    return np.random.default_rng(seed).normal(scale=scale, size=(n, dim))


def _min_eig_ok(cov):
    """Smallest eigenvalue of a covariance matrix >= -1e-9 * trace."""
    assert np.allclose(cov, cov.T, rtol=0, atol=1e-12 * np.trace(cov))
    eig = np.linalg.eigvalsh(cov)
    return eig[0] >= -1e-9 * np.trace(cov), eig[0]


SM1 = dict(weights=np.array([0.5, 1.2, 0.3]),
           means=np.array([[0.0], [0.13], [0.41]]),
           variances=np.array([[0.004], [0.01], [0.002]]))
SM2 = dict(weights=np.array([0.3, 0.7, 1.1]),
           means=np.array([[0.1, 0.2], [0.3, -0.1], [0.0, 0.05]]),
           variances=np.array([[0.01, 0.02], [0.005, 0.01], [0.02, 0.003]]))
ROT = dict(variance=2.5, lengthscales=np.array([3.0, 0.7]), angle=0.4)


def _additive_fns():
    def rx(t):
        return A.spectral_mixture(t, SM1["weights"], SM1["means"], SM1["variances"])

    def ry(t):
        return A.matern(t, 0.8, 2.0, 1.5)

    return rx, ry


# --------------------------------------------------------------------------- pairwise_lags, rotate

def test_pairwise_lags_shape_and_values():
    x1 = _points(4, 2, seed=3)
    x2 = _points(5, 2, seed=4)
    lags = A.pairwise_lags(x1, x2)
    assert lags.shape == (4, 5, 2)
    for i in range(4):
        for j in range(5):
            np.testing.assert_array_equal(lags[i, j], x2[j] - x1[i])
    same = A.pairwise_lags(x1)
    assert same.shape == (4, 4, 2)
    np.testing.assert_array_equal(np.diagonal(same, axis1=0, axis2=1), 0.0)
    np.testing.assert_array_equal(same, -same.transpose(1, 0, 2))


@pytest.mark.parametrize("x1,x2", [(np.zeros((3, 2)), np.zeros((3, 1))),
                                   (np.zeros(3), np.zeros((3, 1))),
                                   (np.zeros((3, 1)), np.zeros((2, 2, 1)))])
def test_pairwise_lags_bad_shapes(x1, x2):
    with pytest.raises(ValueError, match="x1 and x2"):
        A.pairwise_lags(x1, x2)


@pytest.mark.parametrize("phi", [0.0, 0.3, PI / 6, 1.2, -0.7, 2.9])
def test_rotate_maps_direction_phi_onto_first_axis(phi):
    d = 2.7
    along = d * np.array([math.cos(phi), math.sin(phi)])
    across = d * np.array([-math.sin(phi), math.cos(phi)])
    np.testing.assert_allclose(A.rotate(along, phi), [d, 0.0], atol=1e-14)
    np.testing.assert_allclose(A.rotate(across, phi), [0.0, d], atol=1e-14)
    # T_phi is orthogonal: lengths are kept
    lags = _random_lags(50, 2)
    np.testing.assert_allclose(np.linalg.norm(A.rotate(lags, phi), axis=-1),
                               np.linalg.norm(lags, axis=-1), rtol=1e-13)


# --------------------------------------------------------------------------- rotated exponential

@pytest.mark.parametrize("phi", [0.0, PI / 6, 1.0, -0.4, 2.5])
def test_rotated_exponential_known_values(phi):
    var, la, lb = 10.0, 5.0, 0.5
    ls = np.array([la, lb])
    c, s = math.cos(phi), math.sin(phi)
    assert A.rotated_exponential([0.0, 0.0], var, ls, phi) == pytest.approx(var, rel=1e-15)
    np.testing.assert_allclose(A.rotated_exponential([la * c, la * s], var, ls, phi),
                               var * math.exp(-1.0), rtol=1e-13)
    np.testing.assert_allclose(A.rotated_exponential([-lb * s, lb * c], var, ls, phi),
                               var * math.exp(-1.0), rtol=1e-13)
    # a general lag: sqrt((a/la)^2 + (b/lb)^2) in rotated coordinates (a, b)
    a, b = 1.3, -0.2
    lag = a * np.array([c, s]) + b * np.array([-s, c])
    np.testing.assert_allclose(A.rotated_exponential(lag, var, ls, phi),
                               var * math.exp(-math.hypot(a / la, b / lb)), rtol=1e-13)


def test_rotated_exponential_shapes():
    lags = _random_lags(24, 2).reshape(2, 3, 4, 2)
    out = A.rotated_exponential(lags, **ROT)
    assert out.shape == (2, 3, 4)
    assert out.dtype == np.float64


def test_rotated_exponential_isotropic_is_matern_half():
    lags = _random_lags(100, 2)
    np.testing.assert_allclose(A.rotated_exponential(lags, 1.7, [2.0, 2.0], 0.83),
                               A.matern(lags, 1.7, 2.0, 0.5), rtol=1e-13)


def test_rotated_exponential_angle_has_period_pi():
    lags = _random_lags(100, 2)
    base = A.rotated_exponential(lags, 1.0, [4.0, 1.0], 0.3)
    np.testing.assert_allclose(A.rotated_exponential(lags, 1.0, [4.0, 1.0], 0.3 + PI),
                               base, rtol=1e-12)
    np.testing.assert_allclose(A.rotated_exponential(lags, 1.0, [4.0, 1.0], 0.3 - PI),
                               base, rtol=1e-12)


@pytest.mark.parametrize("phi", [0.0, PI / 6, PI / 4, 1.0, 2.0, 3.0, -0.5, 4.0])
def test_rotated_exponential_grooves_run_along_angle(phi):
    """With lengthscales (5, 1), the correlation at a distance d is largest along phi."""
    d = 2.0
    theta = np.deg2rad(np.arange(0.0, 180.0, 0.1))
    lags = d * np.stack([np.cos(theta), np.sin(theta)], axis=-1)
    r = A.rotated_exponential(lags, 1.0, [5.0, 1.0], phi)
    best = theta[np.argmax(r)]
    diff = (best - phi) % PI
    diff = min(diff, PI - diff)
    assert np.rad2deg(diff) <= 1.0
    # and smallest across it
    worst = theta[np.argmin(r)]
    diff = (worst - phi - PI / 2) % PI
    assert np.rad2deg(min(diff, PI - diff)) <= 1.0


def test_rotated_exponential_angle_zero_grooves_along_x():
    for d in (0.5, 1.0, 3.0):
        along_x = A.rotated_exponential([d, 0.0], 1.0, [5.0, 1.0], 0.0)
        along_y = A.rotated_exponential([0.0, d], 1.0, [5.0, 1.0], 0.0)
        assert along_x > along_y
    # at angle pi/2 the roles swap
    assert (A.rotated_exponential([0.0, 1.0], 1.0, [5.0, 1.0], PI / 2)
            > A.rotated_exponential([1.0, 0.0], 1.0, [5.0, 1.0], PI / 2))


def test_rotated_exponential_psd_at_zero_and_symmetry():
    var, ls, phi = 3.0, np.array([4.0, 0.25]), 0.7
    assert A.rotated_exponential_psd([0.0, 0.0], var, ls, phi) == pytest.approx(
        2 * PI * var * 4.0 * 0.25, rel=1e-14)
    f = _random_lags(200, 2, scale=0.5)
    s = A.rotated_exponential_psd(f, var, ls, phi)
    assert s.shape == (200,)
    assert np.all(s > 0)
    np.testing.assert_allclose(A.rotated_exponential_psd(-f, var, ls, phi), s, rtol=1e-14)


def test_rotated_exponential_psd_integrates_to_variance():
    """Polar integration: trapezoid (spectrally accurate, periodic) in angle, quad in radius."""
    var, ls, phi = 2.5, np.array([3.0, 0.7]), 0.4
    theta = np.linspace(0.0, 2 * PI, 128, endpoint=False)
    u = np.stack([np.cos(theta), np.sin(theta)], axis=-1)

    def radial(r):
        return A.rotated_exponential_psd(r * u, var, ls, phi) * r

    inner, _ = integrate.quad_vec(radial, 0.0, np.inf, epsrel=1e-11, epsabs=0)
    total = inner.mean() * 2 * PI
    assert total == pytest.approx(var, rel=1e-7)


def test_rotated_exponential_psd_orientation_and_isotropic_case():
    # long correlation along phi: spectrum falls off fast along phi, slow across it
    phi, f = 0.6, 0.3
    along = f * np.array([math.cos(phi), math.sin(phi)])
    across = f * np.array([-math.sin(phi), math.cos(phi)])
    assert (A.rotated_exponential_psd(along, 1.0, [5.0, 1.0], phi)
            < A.rotated_exponential_psd(across, 1.0, [5.0, 1.0], phi))
    freqs = _random_lags(50, 2, scale=0.4)
    np.testing.assert_allclose(A.rotated_exponential_psd(freqs, 1.3, [0.9, 0.9], 1.1),
                               A.matern_psd(freqs, 1.3, 0.9, 0.5), rtol=1e-13)


# --------------------------------------------------------------------------- spectral mixture

def test_spectral_mixture_at_zero_is_sum_of_weights():
    for p in (SM1, SM2):
        d = p["means"].shape[1]
        assert A.spectral_mixture(np.zeros(d), **p) == pytest.approx(p["weights"].sum(), rel=1e-15)


def test_spectral_mixture_known_value_2d():
    w, mu, v = 1.7, np.array([[0.1, 0.2]]), np.array([[0.01, 0.02]])
    # phase 0.1*1 + 0.2*2 = 0.5 -> cos(pi) = -1; decay 0.01*1 + 0.02*4 = 0.09
    np.testing.assert_allclose(A.spectral_mixture([1.0, 2.0], [w], mu, v),
                               -w * math.exp(-2 * PI**2 * 0.09), rtol=1e-14)


def test_spectral_mixture_single_zero_mean_component_is_squared_exponential():
    w, v = 2.3, 0.015
    lengthscale = 1.0 / (2 * PI * math.sqrt(v))
    tau = np.linspace(-20, 20, 301)[:, None]
    np.testing.assert_allclose(A.spectral_mixture(tau, [w], [[0.0]], [[v]]),
                               w * np.exp(-2 * PI**2 * v * tau[:, 0] ** 2), rtol=1e-12)
    np.testing.assert_allclose(A.spectral_mixture(tau, [w], [[0.0]], [[v]]),
                               A.matern(tau, w, lengthscale, math.inf), rtol=1e-12)


def test_spectral_mixture_eq21_in_2d():
    """Eq 21: cosine of the *summed* phase tau^T mu_q (not a product of per-axis cosines)
    times the Gaussian factor exp(-2 pi^2 tau^T Sigma_q tau), summed over components."""
    tau = _random_lags(60, 2, scale=3.0)
    expect = 0.0
    for q in range(3):
        mu, v = SM2["means"][q], SM2["variances"][q]
        expect = expect + SM2["weights"][q] * np.cos(2 * PI * tau @ mu) * np.exp(
            -2 * PI**2 * (tau**2) @ v)
    np.testing.assert_allclose(A.spectral_mixture(tau, **SM2), expect, rtol=1e-12, atol=1e-14)


def test_spectral_mixture_is_inverse_transform_of_its_psd_2d():
    """r(tau) = int S(f) cos(2 pi f^T tau) df (eq 5), on a fine frequency grid."""
    h = 0.004
    g = np.arange(-1.2, 1.2 + h / 2, h)
    fx, fy = np.meshgrid(g, g, indexing="ij")
    f = np.stack([fx, fy], axis=-1)
    s = A.spectral_mixture_psd(f, **SM2)
    for lag in ([0.0, 0.0], [1.0, 0.0], [0.0, 2.0], [1.5, -2.5], [4.0, 3.0]):
        lag = np.array(lag)
        r = (s * np.cos(2 * PI * f @ lag)).sum() * h * h
        assert r == pytest.approx(float(A.spectral_mixture(lag, **SM2)), abs=1e-10)


def test_spectral_mixture_psd_integrates_to_sum_of_weights_1d():
    def s(f):
        return float(A.spectral_mixture_psd(np.array([f]), **SM1))
    # a finite range with the peaks as break points (quad on an infinite range can miss
    # narrow peaks); the mass beyond |f| = 2 is below 1e-300
    total, _ = integrate.quad(s, -2.0, 2.0, points=[-0.41, -0.13, 0.0, 0.13, 0.41],
                              limit=200, epsabs=1e-13, epsrel=1e-12)
    assert total == pytest.approx(SM1["weights"].sum(), rel=1e-9)


def test_spectral_mixture_psd_integrates_to_sum_of_weights_2d():
    h = 0.004
    g = np.arange(-1.2, 1.2 + h / 2, h)
    fx, fy = np.meshgrid(g, g, indexing="ij")
    s = A.spectral_mixture_psd(np.stack([fx, fy], axis=-1), **SM2)
    assert s.shape == fx.shape
    assert np.all(s >= 0)
    assert s.sum() * h * h == pytest.approx(SM2["weights"].sum(), rel=1e-9)


def test_spectral_mixture_psd_is_even_and_fourier_pair_1d():
    f = np.linspace(-1, 1, 41)[:, None]
    np.testing.assert_allclose(A.spectral_mixture_psd(-f, **SM1),
                               A.spectral_mixture_psd(f, **SM1), rtol=1e-14)
    # S(f) = int r(tau) cos(2 pi f tau) d tau   (eq 5 for an even r)
    for freq in (0.0, 0.1, 0.37):
        val, _ = integrate.quad(lambda t: float(A.spectral_mixture(np.array([t]), **SM1)),
                                0.0, 60.0, weight="cos", wvar=2 * PI * freq, limit=400)
        assert 2 * val == pytest.approx(float(A.spectral_mixture_psd(np.array([freq]), **SM1)),
                                        rel=1e-7, abs=1e-9)


# --------------------------------------------------------------------------- additive

def test_additive_is_sum_of_axis_acvfs():
    rx, ry = _additive_fns()
    for a, b in [(0.0, 0.0), (1.5, -2.0), (-7.0, 0.3), (12.0, 40.0)]:
        expect = rx(np.array([a])) + ry(np.array([b]))
        np.testing.assert_allclose(A.additive(np.array([a, b]), rx, ry), expect, rtol=1e-14)
    lags = _random_lags(30, 2).reshape(5, 6, 2)
    out = A.additive(lags, rx, ry)
    assert out.shape == (5, 6)
    np.testing.assert_allclose(out, rx(lags[..., :1]) + ry(lags[..., 1:]), rtol=1e-14)
    # does not decay along an axis: at (t, 0) it stays >= r_y(0) - |r_x(t)|
    assert A.additive(np.array([1e6, 0.0]), rx, ry) == pytest.approx(float(ry(np.array([0.0]))))


# --------------------------------------------------------------------------- matern

def _matern_bessel(r, var, ls, nu):
    """General Matérn formula (R&W eq 4.14) with the modified Bessel function K_nu."""
    z = math.sqrt(2 * nu) * r / ls
    return var * 2 ** (1 - nu) / special.gamma(nu) * z**nu * special.kv(nu, z)


@pytest.mark.parametrize("nu", [0.5, 1.5, 2.5])
def test_matern_agrees_with_bessel_form(nu):
    var, ls = 1.9, 1.3
    r = np.array([0.01, 0.2, 0.9, 1.3, 2.5, 6.0])
    np.testing.assert_allclose(A.matern(r[:, None], var, ls, nu),
                               _matern_bessel(r, var, ls, nu), rtol=1e-10)


def test_matern_closed_forms_at_hand_picked_distances():
    var, ls = 2.0, 1.5
    e = math.exp(-1.0)
    assert A.matern([0.0], var, ls, 0.5) == pytest.approx(var, rel=1e-15)
    assert A.matern([ls], var, ls, 0.5) == pytest.approx(var * e, rel=1e-14)
    assert A.matern([-2 * ls], var, ls, 0.5) == pytest.approx(var * e**2, rel=1e-14)
    assert A.matern([ls / math.sqrt(3)], var, ls, 1.5) == pytest.approx(2 * var * e, rel=1e-14)
    assert A.matern([ls / math.sqrt(5)], var, ls, 2.5) == pytest.approx(7 / 3 * var * e, rel=1e-14)
    assert A.matern([ls], var, ls, math.inf) == pytest.approx(var * math.exp(-0.5), rel=1e-14)
    for nu in A.MATERN_NUS:
        assert A.matern([0.0], var, ls, nu) == pytest.approx(var, rel=1e-15)
        # isotropic: depends on |tau| only
        assert A.matern([3.0, 4.0], var, ls, nu) == pytest.approx(
            float(A.matern([5.0], var, ls, nu)), rel=1e-14)
        assert A.matern([0.0, 5.0, 0.0], var, ls, nu) == pytest.approx(
            float(A.matern([5.0], var, ls, nu)), rel=1e-14)


@pytest.mark.parametrize("nu", A.MATERN_NUS)
def test_matern_psd_integrates_to_variance(nu):
    var, ls = 1.7, 0.8
    total, _ = integrate.quad(lambda f: float(A.matern_psd(np.array([f]), var, ls, nu)),
                              -np.inf, np.inf, epsabs=1e-13, epsrel=1e-11, limit=200)
    assert total == pytest.approx(var, rel=1e-7)
    # D = 2, radially: 2 pi int S(r) r dr
    total2, _ = integrate.quad(lambda r: float(A.matern_psd(np.array([r, 0.0]), var, ls, nu)) * r,
                               0.0, np.inf, epsabs=1e-13, epsrel=1e-11, limit=200)
    assert 2 * PI * total2 == pytest.approx(var, rel=1e-7)


@pytest.mark.parametrize("nu", A.MATERN_NUS)
def test_matern_psd_is_fourier_transform_1d(nu):
    var, ls = 1.2, 0.9
    # S(0) = int r(tau) d tau; nu = 1/2: 2 var ls
    if nu == 0.5:
        assert A.matern_psd([0.0], var, ls, nu) == pytest.approx(2 * var * ls, rel=1e-14)
    for freq in (0.0, 0.15, 0.6):
        val, _ = integrate.quad(lambda t: float(A.matern(np.array([t]), var, ls, nu)),
                                0.0, 80.0, weight="cos", wvar=2 * PI * freq, limit=400)
        assert 2 * val == pytest.approx(float(A.matern_psd(np.array([freq]), var, ls, nu)),
                                        rel=1e-7)
    f = np.linspace(-2, 2, 21)[:, None]
    np.testing.assert_allclose(A.matern_psd(-f, var, ls, nu), A.matern_psd(f, var, ls, nu),
                               rtol=1e-14)


# --------------------------------------------------------------------------- rectangular

def test_rectangular_values():
    tau = np.array([[-1.5], [-1.0], [-0.3], [0.0], [0.99], [1.0], [1.01], [4.0]])
    np.testing.assert_array_equal(A.rectangular(tau, 2.0, 1.0),
                                  [0.0, 2.0, 2.0, 2.0, 2.0, 2.0, 0.0, 0.0])


def test_rectangular_is_not_positive_semidefinite():
    x = np.linspace(0.0, 10.0, 201)[:, None]
    cov = A.rectangular(A.pairwise_lags(x), 1.0, 1.0)
    ok, smallest = _min_eig_ok(cov)
    assert not ok
    assert smallest < -0.1 * np.max(np.linalg.eigvalsh(cov))
    # Cholesky (the sampler of eq 10) fails
    with pytest.raises(np.linalg.LinAlgError):
        np.linalg.cholesky(cov)


def test_rectangular_psd_has_negative_lobes():
    var, a = 1.5, 1.0
    f = np.linspace(-3.0, 3.0, 601)[:, None]
    s = A.rectangular_psd(f, var, a)
    assert s.min() < -0.2 * var * a
    assert A.rectangular_psd([0.0], var, a) == pytest.approx(2 * a * var)
    # 2 a sigma^2 sinc(2 a f) at f = 3/(4a): sin(3 pi / 2) / (3 pi / 2) < 0
    assert A.rectangular_psd([0.75], var, a) == pytest.approx(
        2 * a * var * math.sin(1.5 * PI) / (1.5 * PI), rel=1e-12)
    # it is the Fourier transform of the box
    for freq in (0.2, 0.75):
        val, _ = integrate.quad(lambda t: float(A.rectangular(np.array([t]), var, a)), -a, a,
                                weight="cos", wvar=2 * PI * freq)
        assert val == pytest.approx(float(A.rectangular_psd(np.array([freq]), var, a)), rel=1e-10)


# --------------------------------------------------------------------------- symmetry r(tau) = r(-tau)

def _all_acvfs():
    rx, ry = _additive_fns()
    out = [("rotated_exponential", 2, lambda t: A.rotated_exponential(t, **ROT)),
           ("spectral_mixture_1d", 1, lambda t: A.spectral_mixture(t, **SM1)),
           ("spectral_mixture_2d", 2, lambda t: A.spectral_mixture(t, **SM2)),
           ("additive", 2, lambda t: A.additive(t, rx, ry)),
           ("rectangular", 1, lambda t: A.rectangular(t, 1.0, 2.0))]
    for nu in A.MATERN_NUS:
        for d in (1, 2):
            out.append((f"matern_{nu}_{d}d", d, lambda t, nu=nu: A.matern(t, 1.3, 1.7, nu)))
    return out


ALL_ACVFS = _all_acvfs()
PSD_ACVFS = [a for a in ALL_ACVFS if a[0] != "rectangular"]


@pytest.mark.parametrize("name,dim,fn", ALL_ACVFS, ids=[a[0] for a in ALL_ACVFS])
def test_symmetry(name, dim, fn):
    lags = _random_lags(300, dim, seed=7, scale=4.0)
    np.testing.assert_allclose(fn(-lags), fn(lags), rtol=1e-13, atol=1e-15)


@pytest.mark.parametrize("name,dim,fn", PSD_ACVFS, ids=[a[0] for a in PSD_ACVFS])
def test_covariance_is_positive_semidefinite(name, dim, fn):
    x = _points(200, dim, seed=11)
    cov = fn(A.pairwise_lags(x))
    assert cov.shape == (200, 200)
    ok, smallest = _min_eig_ok(cov)
    assert ok, f"{name}: smallest eigenvalue {smallest}"


def test_spectral_mixture_many_components_psd():
    rng = np.random.default_rng(5)
    for dim in (1, 2):
        q = 6
        w = rng.uniform(0.1, 2.0, q)
        mu = rng.uniform(-0.5, 0.5, (q, dim))
        v = rng.uniform(0.001, 0.05, (q, dim))
        x = _points(200, dim, seed=12)
        ok, smallest = _min_eig_ok(A.spectral_mixture(A.pairwise_lags(x), w, mu, v))
        assert ok, smallest


# --------------------------------------------------------------------------- NumPy vs torch

def _t(x):
    return torch.as_tensor(np.asarray(x, dtype=np.float64))


def _np_torch_cases():
    rx, ry = _additive_fns()
    lags2 = _random_lags(80, 2, seed=21)
    lags1 = _random_lags(80, 1, seed=22)
    lags2[0] = 0.0
    lags1[0] = 0.0
    cases = [
        ("rotate", lags2, lambda t, m: A.rotate(t, m.as_(0.4))),
        ("rotated_exponential", lags2,
         lambda t, m: A.rotated_exponential(t, m.as_(2.5), m.as_([3.0, 0.7]), m.as_(0.4))),
        ("rotated_exponential_psd", lags2 / 10,
         lambda t, m: A.rotated_exponential_psd(t, m.as_(2.5), m.as_([3.0, 0.7]), m.as_(0.4))),
        ("spectral_mixture", lags2,
         lambda t, m: A.spectral_mixture(t, *(m.as_(SM2[k]) for k in ("weights", "means", "variances")))),
        ("spectral_mixture_psd", lags2 / 10,
         lambda t, m: A.spectral_mixture_psd(t, *(m.as_(SM2[k]) for k in ("weights", "means", "variances")))),
        ("additive", lags2, lambda t, m: A.additive(t, rx, ry)),
        ("rectangular", lags1, lambda t, m: A.rectangular(t, m.as_(1.5), m.as_(2.0))),
        ("pairwise_lags", lags2[:7], lambda t, m: A.pairwise_lags(t, t[:5] + 1)),
    ]
    for nu in A.MATERN_NUS:
        cases.append((f"matern_{nu}", lags2,
                      lambda t, m, nu=nu: A.matern(t, m.as_(1.3), m.as_(1.7), nu)))
        cases.append((f"matern_psd_{nu}", lags2 / 10,
                      lambda t, m, nu=nu: A.matern_psd(t, m.as_(1.3), m.as_(1.7), nu)))
    return cases


class _NP:
    @staticmethod
    def as_(x):
        return np.asarray(x, dtype=np.float64)


class _TORCH:
    @staticmethod
    def as_(x):
        return _t(x)


NP_TORCH = _np_torch_cases()


@pytest.mark.parametrize("name,lags,fn", NP_TORCH, ids=[c[0] for c in NP_TORCH])
def test_numpy_and_torch_agree(name, lags, fn):
    out_np = fn(lags, _NP)
    out_t = fn(_t(lags), _TORCH)
    assert isinstance(out_np, np.ndarray)
    assert isinstance(out_t, torch.Tensor)
    assert out_np.dtype == np.float64
    assert out_t.dtype == torch.float64
    assert out_t.shape == out_np.shape
    np.testing.assert_allclose(out_t.numpy(), out_np, rtol=1e-14, atol=1e-14)


def test_rectangular_psd_accepts_tensor():
    f = np.linspace(-2, 2, 11)[:, None]
    np.testing.assert_allclose(np.asarray(A.rectangular_psd(_t(f), 1.5, 2.0)),
                               A.rectangular_psd(f, 1.5, 2.0), rtol=1e-14)


def _grad_cases():
    return ([("rotated_exponential", 2, lambda t, p: A.rotated_exponential(t, p[0], p[1], p[2]),
              [2.0, [3.0, 0.7], 0.4])]
            + [(f"matern_{nu}_{d}d", d, lambda t, p, nu=nu: A.matern(t, p[0], p[1], nu), [1.3, 1.7])
               for nu in A.MATERN_NUS for d in (1, 2)]
            + [("spectral_mixture", 2, lambda t, p: A.spectral_mixture(t, p[0], p[1], p[2]),
                [SM2["weights"], SM2["means"], SM2["variances"]])])


GRADS = _grad_cases()


@pytest.mark.parametrize("name,dim,fn,params", GRADS, ids=[g[0] for g in GRADS])
def test_torch_gradients_finite_at_zero_lag(name, dim, fn, params):
    lags = torch.zeros(3, dim, dtype=torch.float64)
    lags[1] = 0.5
    lags.requires_grad_(True)
    ps = [torch.tensor(np.asarray(p, dtype=np.float64), requires_grad=True) for p in params]
    out = fn(lags, ps)
    out.sum().backward()
    assert torch.all(torch.isfinite(lags.grad))
    for p in ps:
        assert p.grad is not None
        assert torch.all(torch.isfinite(p.grad))
    # the exponential and Matern kernels are even: the gradient at lag 0 itself is 0
    # (one-sided slopes cancel), never NaN
    assert torch.all(lags.grad[0] == 0)
    # gradient of a matrix built with pairwise_lags (zeros on the diagonal)
    x = torch.tensor(_points(6, dim), requires_grad=True)
    ps = [torch.tensor(np.asarray(p, dtype=np.float64), requires_grad=True) for p in params]
    fn(A.pairwise_lags(x), ps).sum().backward()
    assert torch.all(torch.isfinite(x.grad))
    assert all(torch.all(torch.isfinite(p.grad)) for p in ps)


# --------------------------------------------------------------------------- input checks

L2 = np.zeros((4, 2))
L1 = np.zeros((4, 1))
NAN, INF = float("nan"), float("inf")
BAD_SCALARS = [0.0, -1.0, NAN, INF, -INF]


@pytest.mark.parametrize("bad", BAD_SCALARS)
def test_bad_variance(bad):
    with pytest.raises(ValueError, match="variance"):
        A.rotated_exponential(L2, bad, [1.0, 1.0], 0.0)
    with pytest.raises(ValueError, match="variance"):
        A.rotated_exponential_psd(L2, bad, [1.0, 1.0], 0.0)
    for nu in A.MATERN_NUS:
        with pytest.raises(ValueError, match="variance"):
            A.matern(L1, bad, 1.0, nu)
        with pytest.raises(ValueError, match="variance"):
            A.matern_psd(L1, bad, 1.0, nu)
    with pytest.raises(ValueError, match="variance"):
        A.rectangular(L1, bad, 1.0)
    with pytest.raises(ValueError, match="variance"):
        A.rectangular_psd(L1, bad, 1.0)


@pytest.mark.parametrize("bad", BAD_SCALARS)
def test_bad_lengthscales(bad):
    for ls in ([bad, 1.0], [1.0, bad]):
        with pytest.raises(ValueError, match="lengthscales"):
            A.rotated_exponential(L2, 1.0, ls, 0.0)
        with pytest.raises(ValueError, match="lengthscales"):
            A.rotated_exponential_psd(L2, 1.0, ls, 0.0)
    with pytest.raises(ValueError, match="lengthscale"):
        A.matern(L1, 1.0, bad, 0.5)
    with pytest.raises(ValueError, match="lengthscale"):
        A.matern_psd(L1, 1.0, bad, 1.5)
    with pytest.raises(ValueError, match="width"):
        A.rectangular(L1, 1.0, bad)
    with pytest.raises(ValueError, match="width"):
        A.rectangular_psd(L1, 1.0, bad)


@pytest.mark.parametrize("bad", BAD_SCALARS)
def test_bad_mixture_weights_and_variances(bad):
    w, mu, v = SM2["weights"].copy(), SM2["means"], SM2["variances"].copy()
    w[1] = bad
    with pytest.raises(ValueError, match="weights"):
        A.spectral_mixture(L2, w, mu, SM2["variances"])
    with pytest.raises(ValueError, match="weights"):
        A.spectral_mixture_psd(L2, w, mu, SM2["variances"])
    v[2, 1] = bad
    with pytest.raises(ValueError, match="variances"):
        A.spectral_mixture(L2, SM2["weights"], mu, v)
    with pytest.raises(ValueError, match="variances"):
        A.spectral_mixture_psd(L2, SM2["weights"], mu, v)


@pytest.mark.parametrize("bad", [NAN, INF])
def test_nonfinite_means(bad):
    mu = SM2["means"].copy()
    mu[0, 0] = bad
    for fn in (A.spectral_mixture, A.spectral_mixture_psd):
        with pytest.raises(ValueError, match="means"):
            fn(L2, SM2["weights"], mu, SM2["variances"])


def test_wrong_shapes():
    with pytest.raises(ValueError, match="lengthscales"):
        A.rotated_exponential(L2, 1.0, [1.0, 2.0, 3.0], 0.0)
    with pytest.raises(ValueError, match="lengthscales"):
        A.rotated_exponential_psd(L2, 1.0, [1.0], 0.0)
    with pytest.raises(ValueError, match="variance"):
        A.rotated_exponential(L2, [1.0, 2.0], [1.0, 2.0], 0.0)
    with pytest.raises(ValueError, match="angle"):
        A.rotated_exponential(L2, 1.0, [1.0, 2.0], [0.0, 1.0])
    with pytest.raises(ValueError, match="lengthscale"):
        A.matern(L1, 1.0, [1.0, 2.0], 0.5)
    with pytest.raises(ValueError, match="variance"):
        A.matern(L1, [1.0], 1.0, 0.5)
    # lags whose last axis is not D
    with pytest.raises(ValueError, match="lags"):
        A.rotated_exponential(np.zeros((4, 3)), 1.0, [1.0, 2.0], 0.0)
    with pytest.raises(ValueError, match="lags"):
        A.rotated_exponential(np.zeros(4), 1.0, [1.0, 2.0], 0.0)
    with pytest.raises(ValueError, match="freqs"):
        A.rotated_exponential_psd(np.zeros((4, 1)), 1.0, [1.0, 2.0], 0.0)
    with pytest.raises(ValueError, match="lags"):
        A.spectral_mixture(np.zeros((4, 1)), **SM2)
    with pytest.raises(ValueError, match="freqs"):
        A.spectral_mixture_psd(np.zeros((4, 3)), **SM2)
    with pytest.raises(ValueError, match="lags"):
        A.additive(np.zeros((4, 1)), *_additive_fns())
    with pytest.raises(ValueError, match="lags"):
        A.rectangular(np.zeros((4, 2)), 1.0, 1.0)
    with pytest.raises(ValueError, match="freqs"):
        A.rectangular_psd(np.zeros((4, 2)), 1.0, 1.0)
    with pytest.raises(ValueError, match="lags"):
        A.matern(np.float64(1.0), 1.0, 1.0, 0.5)
    with pytest.raises(ValueError, match="freqs"):
        A.matern_psd(np.float64(1.0), 1.0, 1.0, 0.5)


def test_wrong_mixture_shapes():
    w, mu, v = SM2["weights"], SM2["means"], SM2["variances"]
    for fn in (A.spectral_mixture, A.spectral_mixture_psd):
        # means not (Q, D)
        with pytest.raises(ValueError, match="means"):
            fn(L2, w, mu[:, 0], v)
        with pytest.raises(ValueError, match="means"):
            fn(L2, w, mu[None], v)
        # weights of the wrong length
        with pytest.raises(ValueError, match="weights"):
            fn(L2, w[:2], mu, v)
        with pytest.raises(ValueError, match="weights"):
            fn(L2, w[:, None], mu, v)
        # variances not (Q, D)
        with pytest.raises(ValueError, match="variances"):
            fn(L2, w, mu, v[:, :1])
        with pytest.raises(ValueError, match="variances"):
            fn(L2, w, mu, v[:2])


def test_means_with_wrong_number_of_components_is_blamed_on_means():
    """means of shape (Q', D) while weights (Q,) and variances (Q, D) agree on Q: the
    message must name the parameter that is wrong, the means."""
    w, mu, v = SM2["weights"], SM2["means"], SM2["variances"]
    for fn in (A.spectral_mixture, A.spectral_mixture_psd):
        with pytest.raises(ValueError, match="means"):
            fn(L2, w, mu[:2], v)


@pytest.mark.parametrize("bad", [NAN, INF])
def test_nonfinite_lags(bad):
    l2 = _random_lags(5, 2)
    l2[3, 1] = bad
    l1 = l2[:, :1].copy()
    l1[2, 0] = bad
    rx, ry = _additive_fns()
    with pytest.raises(ValueError, match="lags"):
        A.rotated_exponential(l2, **ROT)
    with pytest.raises(ValueError, match="freqs"):
        A.rotated_exponential_psd(l2, **ROT)
    with pytest.raises(ValueError, match="lags"):
        A.spectral_mixture(l2, **SM2)
    with pytest.raises(ValueError, match="freqs"):
        A.spectral_mixture_psd(l2, **SM2)
    with pytest.raises(ValueError, match="lags"):
        A.additive(l2, rx, ry)
    for nu in A.MATERN_NUS:
        with pytest.raises(ValueError, match="lags"):
            A.matern(l2, 1.0, 1.0, nu)
        with pytest.raises(ValueError, match="freqs"):
            A.matern_psd(l1, 1.0, 1.0, nu)
    with pytest.raises(ValueError, match="lags"):
        A.rectangular(l1, 1.0, 1.0)
    with pytest.raises(ValueError, match="freqs"):
        A.rectangular_psd(l1, 1.0, 1.0)
    # torch tensors are checked too
    with pytest.raises(ValueError, match="lags"):
        A.rotated_exponential(_t(l2), **ROT)
    with pytest.raises(ValueError, match="lags"):
        A.matern(_t(l2).requires_grad_(True), 1.0, 1.0, 0.5)


@pytest.mark.parametrize("bad", [NAN, INF])
def test_nonfinite_angle(bad):
    with pytest.raises(ValueError, match="angle"):
        A.rotated_exponential(L2, 1.0, [1.0, 2.0], bad)
    with pytest.raises(ValueError, match="angle"):
        A.rotated_exponential_psd(L2, 1.0, [1.0, 2.0], bad)
    with pytest.raises(ValueError, match="angle"):
        A.rotated_exponential(_t(L2), 1.0, [1.0, 2.0], torch.tensor(bad, dtype=torch.float64))


@pytest.mark.parametrize("nu", [1.0, 0.0, 2.0, 3.5, -0.5])
def test_matern_bad_nu(nu):
    with pytest.raises(ValueError, match="nu"):
        A.matern(L1, 1.0, 1.0, nu)
    with pytest.raises(ValueError, match="nu"):
        A.matern_psd(L1, 1.0, 1.0, nu)


def test_bad_tensor_hyperparameters():
    with pytest.raises(ValueError, match="variance"):
        A.rotated_exponential(_t(L2), torch.tensor(-1.0, dtype=torch.float64),
                              _t([1.0, 2.0]), _t(0.0))
    with pytest.raises(ValueError, match="lengthscales"):
        A.rotated_exponential(_t(L2), _t(1.0), torch.tensor([1.0, NAN], dtype=torch.float64,
                                                            requires_grad=True), _t(0.0))
    with pytest.raises(ValueError, match="weights"):
        A.spectral_mixture(_t(L2), _t([1.0, -1.0]), _t(np.zeros((2, 2))), _t(np.ones((2, 2))))
