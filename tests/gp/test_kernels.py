"""Tests of roughgp.gp.kernels: the GPyTorch kernels evaluate the plain ACVFs of roughgp.gp.acvf
(eq 18, 21, 22, Matérn), keep their hyperparameters positive and learnable, and validate input."""

from __future__ import annotations

import math

import gpytorch
import numpy as np
import pytest
import torch

from roughgp.gp import acvf as A
from roughgp.gp import kernels as K

PI = math.pi
F64 = torch.float64


def _x(n, dim, seed=0, size=10.0):
    return torch.as_tensor(np.random.default_rng(seed).uniform(0.0, size, size=(n, dim)), dtype=F64)


def _np(t):
    return t.detach().cpu().numpy()


SM1 = dict(weights=np.array([0.5, 1.2, 0.3]),
           means=np.array([[0.05], [0.13], [0.41]]),
           variances=np.array([[0.004], [0.01], [0.002]]))
SM2 = dict(weights=np.array([0.3, 0.7]),
           means=np.array([[0.1, 0.2], [0.3, -0.1]]),
           variances=np.array([[0.01, 0.02], [0.005, 0.01]]))
ROT = dict(variance=2.5, lengthscales=np.array([3.0, 0.7]), angle=0.4)


def _c(params):
    """A copy of a parameter dict, so that no kernel shares memory with the module constants."""
    return {k: np.copy(v) for k, v in params.items()}


def _kernel_cases():
    """(id, kernel factory, dim, plain function of numpy lags, plain psd or None)."""
    cases = [
        ("rotated_exponential", lambda: K.RotatedExponentialKernel(**_c(ROT)), 2,
         lambda t: A.rotated_exponential(t, **ROT),
         lambda f: A.rotated_exponential_psd(f, **ROT)),
        ("spectral_mixture_1d", lambda: K.SpectralMixtureKernel(3, dim=1, **_c(SM1)), 1,
         lambda t: A.spectral_mixture(t, **SM1), lambda f: A.spectral_mixture_psd(f, **SM1)),
        ("spectral_mixture_2d", lambda: K.SpectralMixtureKernel(2, dim=2, **_c(SM2)), 2,
         lambda t: A.spectral_mixture(t, **SM2), lambda f: A.spectral_mixture_psd(f, **SM2)),
        ("additive",
         lambda: K.AdditiveKernel(K.SpectralMixtureKernel(3, **_c(SM1)),
                                  K.MaternKernel(nu=1.5, variance=0.8, lengthscale=2.0)), 2,
         lambda t: A.additive(t, lambda u: A.spectral_mixture(u, **SM1),
                              lambda u: A.matern(u, 0.8, 2.0, 1.5)),
         None),
    ]
    for nu in A.MATERN_NUS:
        for d in (1, 2):
            cases.append((f"matern_{nu}_{d}d",
                          lambda nu=nu, d=d: K.MaternKernel(nu=nu, dim=d, variance=1.3,
                                                            lengthscale=1.7), d,
                          lambda t, nu=nu: A.matern(t, 1.3, 1.7, nu),
                          lambda f, nu=nu: A.matern_psd(f, 1.3, 1.7, nu)))
    return cases


CASES = _kernel_cases()
IDS = [c[0] for c in CASES]
PSD_CASES = [c for c in CASES if c[4] is not None]


# --------------------------------------------------------------------------- agreement with acvf

@pytest.mark.parametrize("name,make,dim,fn,psd", CASES, ids=IDS)
def test_kernel_matrix_equals_acvf_of_pairwise_lags(name, make, dim, fn, psd):
    k = make()
    x1, x2 = _x(40, dim, seed=1), _x(30, dim, seed=2)
    with torch.no_grad():
        full = k(x1, x2).to_dense()
        sym = k(x1).to_dense()
    assert full.shape == (40, 30) and full.dtype == F64
    np.testing.assert_allclose(_np(full), fn(A.pairwise_lags(_np(x1), _np(x2))),
                               rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(_np(sym), fn(A.pairwise_lags(_np(x1))), rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(_np(sym), _np(sym).T, rtol=0, atol=1e-14)
    # R is a valid covariance
    eig = np.linalg.eigvalsh(_np(sym))
    assert eig[0] >= -1e-9 * eig.sum()


@pytest.mark.parametrize("name,make,dim,fn,psd", CASES, ids=IDS)
def test_diag_equals_diagonal_of_full_matrix(name, make, dim, fn, psd):
    k = make()
    x = _x(25, dim, seed=3)
    with torch.no_grad():
        diag = k(x, diag=True)
        full = k(x).to_dense()
    diag = diag.to_dense() if hasattr(diag, "to_dense") else diag
    assert diag.shape == (25,)
    np.testing.assert_allclose(_np(diag), _np(torch.diagonal(full)), rtol=1e-14)
    np.testing.assert_allclose(_np(diag), fn(np.zeros((1, dim)))[0], rtol=1e-14)
    # x1 != x2 of equal length: diag holds r(x2[i] - x1[i])
    y = _x(25, dim, seed=4)
    with torch.no_grad():
        diag_xy = k(x, y, diag=True)
    np.testing.assert_allclose(_np(diag_xy), fn(_np(y) - _np(x)), rtol=1e-12, atol=1e-14)


@pytest.mark.parametrize("name,make,dim,fn,psd", CASES, ids=IDS)
def test_kernel_acvf_numpy_and_tensor(name, make, dim, fn, psd):
    k = make()
    lags = np.random.default_rng(5).normal(scale=3.0, size=(4, 7, dim))
    out = k.acvf(lags)
    assert isinstance(out, np.ndarray) and out.dtype == np.float64 and out.shape == (4, 7)
    np.testing.assert_allclose(out, fn(lags), rtol=1e-13, atol=1e-15)
    # a list in works like an array
    np.testing.assert_allclose(k.acvf(lags.tolist()), fn(lags), rtol=1e-13, atol=1e-15)
    t = k.acvf(torch.as_tensor(lags))
    assert isinstance(t, torch.Tensor) and t.dtype == F64
    assert t.requires_grad
    np.testing.assert_allclose(_np(t), fn(lags), rtol=1e-13, atol=1e-15)
    t.sum().backward()
    grads = [p.grad for p in k.parameters()]
    assert any(g is not None for g in grads)
    assert all(torch.all(torch.isfinite(g)) for g in grads if g is not None)


@pytest.mark.parametrize("name,make,dim,fn,psd", PSD_CASES, ids=[c[0] for c in PSD_CASES])
def test_kernel_psd_equals_plain_psd(name, make, dim, fn, psd):
    k = make()
    freqs = np.random.default_rng(6).normal(scale=0.3, size=(50, dim))
    out = k.psd(freqs)
    assert isinstance(out, np.ndarray) and out.dtype == np.float64
    np.testing.assert_allclose(out, psd(freqs), rtol=1e-13)
    t = k.psd(torch.as_tensor(freqs))
    assert isinstance(t, torch.Tensor)
    np.testing.assert_allclose(_np(t), psd(freqs), rtol=1e-13)


def test_additive_psd_raises_and_parts_have_psds():
    k = K.AdditiveKernel(K.MaternKernel(), K.MaternKernel(nu=2.5))
    with pytest.raises(NotImplementedError):
        k.psd(np.zeros((3, 2)))
    np.testing.assert_allclose(k.kernel_y.psd(np.zeros((1, 1))), A.matern_psd([[0.0]], 1.0, 1.0, 2.5))


def test_additive_kernel_parts_act_on_their_column():
    kx = K.MaternKernel(nu=0.5, variance=2.0, lengthscale=3.0)
    ky = K.MaternKernel(nu=math.inf, variance=0.5, lengthscale=0.4)
    k = K.AdditiveKernel(kx, ky)
    x = _x(20, 2, seed=7)
    with torch.no_grad():
        full = k(x).to_dense()
        parts = kx(x[:, :1]).to_dense() + ky(x[:, 1:]).to_dense()
    np.testing.assert_allclose(_np(full), _np(parts), rtol=1e-14)
    names = {n for n, _ in k.named_parameters()}
    assert {"kernel_x.raw_variance", "kernel_y.raw_variance",
            "kernel_x.raw_lengthscale", "kernel_y.raw_lengthscale"} <= names


# --------------------------------------------------------------------------- vs GPyTorch's SM kernel

def _gpytorch_sm(weights, means, variances):
    q, d = means.shape
    g = gpytorch.kernels.SpectralMixtureKernel(num_mixtures=q, ard_num_dims=d).double()
    g.mixture_weights = torch.as_tensor(weights, dtype=F64)
    g.mixture_means = torch.as_tensor(means, dtype=F64).reshape(q, 1, d)
    g.mixture_scales = torch.as_tensor(np.sqrt(variances), dtype=F64).reshape(q, 1, d)
    return g


def test_spectral_mixture_matches_gpytorch_in_1d():
    ours = K.SpectralMixtureKernel(3, dim=1, **_c(SM1))
    theirs = _gpytorch_sm(**SM1)
    x1, x2 = _x(50, 1, seed=8, size=30.0), _x(40, 1, seed=9, size=30.0)
    with torch.no_grad():
        np.testing.assert_allclose(_np(ours(x1, x2).to_dense()), _np(theirs(x1, x2).to_dense()),
                                   rtol=1e-12, atol=1e-12)
        np.testing.assert_allclose(_np(ours(x1, diag=True)), _np(theirs(x1, diag=True)),
                                   rtol=1e-12, atol=1e-12)


def test_spectral_mixture_differs_from_gpytorch_in_2d():
    """For D > 1 GPyTorch computes prod_d sum_q w_q cos(2 pi tau_d mu_qd) exp(-2 pi^2 tau_d^2 v_qd)
    (components summed per axis, then axes multiplied); eq 21 is
    sum_q w_q cos(2 pi tau^T mu_q) exp(-2 pi^2 tau^T Sigma_q tau). With two components the
    cross terms q != q' of GPyTorch's product make it a different function, so the 2-D kernel
    is deliberately not compared with GPyTorch's for equality."""
    ours = K.SpectralMixtureKernel(2, dim=2, **_c(SM2))
    theirs = _gpytorch_sm(SM2["weights"], np.abs(SM2["means"]), SM2["variances"])
    ours.means = np.abs(SM2["means"])  # GPyTorch constrains its means to be positive
    w, mu, v = SM2["weights"], np.abs(SM2["means"]), SM2["variances"]
    x1, x2 = _x(30, 2, seed=10), _x(20, 2, seed=11)
    with torch.no_grad():
        k_ours = _np(ours(x1, x2).to_dense())
        k_theirs = _np(theirs(x1, x2).to_dense())
    tau = A.pairwise_lags(_np(x1), _np(x2))
    # GPyTorch's formula, written out: sum over components per axis, product over axes
    per_axis = [sum(w[q] * np.cos(2 * PI * tau[..., d] * mu[q, d])
                    * np.exp(-2 * PI**2 * tau[..., d] ** 2 * v[q, d]) for q in range(2))
                for d in range(2)]
    np.testing.assert_allclose(k_theirs, per_axis[0] * per_axis[1], rtol=1e-10, atol=1e-12)
    np.testing.assert_allclose(k_ours, A.spectral_mixture(tau, w, mu, v), rtol=1e-12, atol=1e-12)
    assert np.max(np.abs(k_ours - k_theirs)) > 1e-2
    # already at lag 0: sum_q w_q (ours) vs (sum_q w_q)^D (GPyTorch)
    with torch.no_grad():
        zero = torch.zeros(1, 2, dtype=F64)
        assert ours(zero).to_dense().item() == pytest.approx(w.sum())
        assert theirs(zero).to_dense().item() == pytest.approx(w.sum() ** 2)


# --------------------------------------------------------------------------- learnable, positive

def _nll(kernel, x, y):
    cov = kernel(x).to_dense() + 1e-2 * torch.eye(len(x), dtype=F64)
    return -torch.distributions.MultivariateNormal(torch.zeros(len(x), dtype=F64), cov).log_prob(y)


@pytest.mark.parametrize("name,make,dim,fn,psd", CASES, ids=IDS)
def test_hyperparameters_stay_positive_after_adam_step(name, make, dim, fn, psd):
    k = make()
    x = _x(30, dim, seed=12)
    y = torch.as_tensor(np.random.default_rng(13).normal(size=30), dtype=F64)
    raw = dict(k.named_parameters())
    assert raw, "kernel has no learnable parameters"
    before = {n: p.detach().clone() for n, p in raw.items()}
    # a loss that pushes every variance-like value to 0, plus a likelihood
    loss = k(x).to_dense().sum() + _nll(k, x, y)
    loss.backward()
    for n, p in raw.items():
        assert p.grad is not None, n
        assert torch.all(torch.isfinite(p.grad)), n
    opt = torch.optim.Adam(k.parameters(), lr=20.0)  # a huge step: raw values go far negative
    opt.step()
    assert any(not torch.equal(before[n], p.detach()) for n, p in raw.items())
    for hname, value in k.hyperparameters().items():
        if hname.endswith("angle") or hname.endswith("means"):
            assert torch.all(torch.isfinite(value)), hname
        else:
            assert torch.all(value > 0), (hname, value)
            assert torch.all(torch.isfinite(value)), hname
    # and the kernel still evaluates
    with torch.no_grad():
        assert torch.all(torch.isfinite(k(x).to_dense()))


def test_raw_parameters_are_positively_constrained():
    k = K.RotatedExponentialKernel(**_c(ROT))
    constraints = dict(k.named_constraints())
    assert isinstance(constraints["raw_variance_constraint"], gpytorch.constraints.Positive)
    assert isinstance(constraints["raw_lengthscale_constraint"], gpytorch.constraints.Positive)
    sm = K.SpectralMixtureKernel(2, dim=2, **_c(SM2))
    constraints = dict(sm.named_constraints())
    assert isinstance(constraints["raw_weights_constraint"], gpytorch.constraints.Positive)
    assert isinstance(constraints["raw_variances_constraint"], gpytorch.constraints.Positive)
    # angle and means are unconstrained
    k.angle = -2.0
    assert k.angle.item() == -2.0
    sm.means = -SM2["means"]
    np.testing.assert_array_equal(_np(sm.means), -SM2["means"])


def test_rotated_exponential_angle_gets_gradient():
    k = K.RotatedExponentialKernel(**_c(ROT))
    x = _x(10, 2, seed=14)
    k(x).to_dense().sum().backward()
    assert k.raw_angle.grad is not None and k.raw_angle.grad.item() != 0.0
    assert torch.all(k.raw_lengthscale.grad != 0)


# --------------------------------------------------------------------------- hyperparameter values

def test_hyperparameter_values_round_trip():
    k = K.RotatedExponentialKernel(variance=3.0, lengthscales=(5.0, 1.0), angle=0.3)
    hp = k.hyperparameters()
    assert set(hp) == {"variance", "lengthscales", "angle"}
    assert hp["variance"].item() == pytest.approx(3.0, rel=1e-12)
    np.testing.assert_allclose(_np(hp["lengthscales"]), [5.0, 1.0], rtol=1e-12)
    assert hp["angle"].item() == 0.3
    k.variance = 0.5
    k.lengthscales = [2.0, 7.0]
    k.angle = -1.0
    assert k.variance.item() == pytest.approx(0.5, rel=1e-12)
    np.testing.assert_allclose(_np(k.lengthscales), [2.0, 7.0], rtol=1e-12)
    assert k.angle.item() == -1.0

    sm = K.SpectralMixtureKernel(2, dim=2, **_c(SM2))
    assert sm.num_mixtures == 2 and sm.dim == 2
    assert set(sm.hyperparameters()) == {"weights", "means", "variances"}
    np.testing.assert_allclose(_np(sm.weights), SM2["weights"], rtol=1e-12)
    np.testing.assert_allclose(_np(sm.variances), SM2["variances"], rtol=1e-12)
    sm.weights = [1.0, 2.0]
    np.testing.assert_allclose(_np(sm.weights), [1.0, 2.0], rtol=1e-12)

    m = K.MaternKernel(nu=2.5, dim=2, variance=4.0, lengthscale=0.3)
    assert set(m.hyperparameters()) == {"variance", "lengthscale"}
    assert m.hyperparameters()["lengthscale"].shape == ()
    assert m.hyperparameters()["lengthscale"].item() == pytest.approx(0.3, rel=1e-12)

    add = K.AdditiveKernel(K.MaternKernel(), K.SpectralMixtureKernel(2))
    assert set(add.hyperparameters()) == {"x.variance", "x.lengthscale",
                                          "y.weights", "y.means", "y.variances"}


def test_spectral_mixture_defaults():
    sm = K.SpectralMixtureKernel(4, dim=2)
    assert sm.weights.shape == (4,) and sm.means.shape == (4, 2) and sm.variances.shape == (4, 2)
    assert sm.weights.dtype == F64
    assert sm.weights.sum().item() == pytest.approx(1.0)
    assert torch.all(sm.variances > 0)


# --------------------------------------------------------------------------- validation

@pytest.mark.parametrize("bad", [-1.0, 0.0, float("nan"), float("inf")])
def test_setters_validate_positive_values(bad):
    k = K.RotatedExponentialKernel(**_c(ROT))
    with pytest.raises(ValueError, match="variance"):
        k.variance = bad
    with pytest.raises(ValueError, match="lengthscales"):
        k.lengthscales = [1.0, bad]
    m = K.MaternKernel()
    with pytest.raises(ValueError, match="variance"):
        m.variance = bad
    sm = K.SpectralMixtureKernel(2, dim=2, **_c(SM2))
    with pytest.raises(ValueError, match="weights"):
        sm.weights = [1.0, bad]
    with pytest.raises(ValueError, match="variances"):
        sm.variances = [[1.0, 1.0], [bad, 1.0]]
    # a rejected value leaves the kernel unchanged
    assert k.variance.item() == pytest.approx(ROT["variance"], rel=1e-12)
    np.testing.assert_allclose(_np(sm.weights), SM2["weights"], rtol=1e-12)


@pytest.mark.parametrize("bad", [float("nan"), float("inf")])
def test_setters_validate_finite_values(bad):
    k = K.RotatedExponentialKernel(**_c(ROT))
    with pytest.raises(ValueError, match="angle"):
        k.angle = bad
    sm = K.SpectralMixtureKernel(2, dim=2, **_c(SM2))
    with pytest.raises(ValueError, match="means"):
        sm.means = [[0.1, bad], [0.0, 0.0]]


def test_setters_validate_shapes():
    k = K.RotatedExponentialKernel(**_c(ROT))
    with pytest.raises(ValueError, match="lengthscales"):
        k.lengthscales = [1.0, 2.0, 3.0]
    with pytest.raises(ValueError, match="lengthscales"):
        k.lengthscales = 1.0
    with pytest.raises(ValueError, match="variance"):
        k.variance = [1.0, 2.0]
    with pytest.raises(ValueError, match="angle"):
        k.angle = [0.1, 0.2]
    sm = K.SpectralMixtureKernel(2, dim=2, **_c(SM2))
    with pytest.raises(ValueError, match="weights"):
        sm.weights = [1.0, 2.0, 3.0]
    with pytest.raises(ValueError, match="means"):
        sm.means = [0.1, 0.2]
    with pytest.raises(ValueError, match="variances"):
        sm.variances = [[0.1], [0.2]]


def test_constructors_validate():
    with pytest.raises(ValueError, match="lengthscales"):
        K.RotatedExponentialKernel(lengthscales=(-1.0, 2.0))
    with pytest.raises(ValueError, match="lengthscales"):
        K.RotatedExponentialKernel(lengthscales=(1.0, 2.0, 3.0))
    with pytest.raises(ValueError, match="variance"):
        K.RotatedExponentialKernel(variance=-2.0)
    with pytest.raises(ValueError, match="angle"):
        K.RotatedExponentialKernel(angle=float("nan"))
    with pytest.raises(ValueError, match="lengthscale"):
        K.MaternKernel(lengthscale=-1.0)
    with pytest.raises(ValueError, match="variance"):
        K.MaternKernel(variance=0.0)
    with pytest.raises(ValueError, match="nu"):
        K.MaternKernel(nu=1.0)
    with pytest.raises(ValueError, match="dim"):
        K.MaternKernel(dim=0)
    with pytest.raises(ValueError, match="num_mixtures"):
        K.SpectralMixtureKernel(0)
    with pytest.raises(ValueError, match="num_mixtures"):
        K.SpectralMixtureKernel(2.0)
    with pytest.raises(ValueError, match="dim"):
        K.SpectralMixtureKernel(2, dim=0)
    with pytest.raises(ValueError, match="weights"):
        K.SpectralMixtureKernel(2, weights=[1.0, -1.0])
    with pytest.raises(ValueError, match="weights"):
        K.SpectralMixtureKernel(2, weights=[1.0, 1.0, 1.0])
    with pytest.raises(ValueError, match="means"):
        K.SpectralMixtureKernel(2, dim=2, means=np.zeros((2, 1)))
    with pytest.raises(ValueError, match="variances"):
        K.SpectralMixtureKernel(2, variances=[[0.1], [float("nan")]])


def test_additive_kernel_rejects_non_1d_parts():
    with pytest.raises(ValueError, match="kernel_x"):
        K.AdditiveKernel(K.RotatedExponentialKernel(), K.MaternKernel())
    with pytest.raises(ValueError, match="kernel_y"):
        K.AdditiveKernel(K.MaternKernel(), K.MaternKernel(dim=2))
    with pytest.raises(ValueError, match="kernel_y"):
        K.AdditiveKernel(K.MaternKernel(), K.SpectralMixtureKernel(1, dim=2))
    with pytest.raises(ValueError, match="kernel_x"):
        K.AdditiveKernel(gpytorch.kernels.RBFKernel(), K.MaternKernel())


@pytest.mark.parametrize("make", [
    lambda **kw: K.RotatedExponentialKernel(**kw),
    lambda **kw: K.SpectralMixtureKernel(2, **kw),
    lambda **kw: K.MaternKernel(**kw),
    lambda **kw: K.AdditiveKernel(K.MaternKernel(), K.MaternKernel(), **kw),
], ids=["rotated_exponential", "spectral_mixture", "matern", "additive"])
def test_batch_shape_rejected(make):
    with pytest.raises(ValueError, match="batch_shape"):
        make(batch_shape=torch.Size([3]))
    make(batch_shape=torch.Size([]))  # empty is fine


@pytest.mark.parametrize("name,make,dim,fn,psd", CASES, ids=IDS)
def test_wrong_number_of_input_columns(name, make, dim, fn, psd):
    k = make()
    x = _x(5, dim + 1, seed=15)
    # RotatedExponentialKernel sets GPyTorch's ard_num_dims = 2, so GPyTorch's own input check
    # (a RuntimeError) fires before roughgp's ValueError; the others raise roughgp's ValueError.
    expected = (ValueError, RuntimeError) if name == "rotated_exponential" else ValueError
    with pytest.raises(expected, match="columns|dimensionality"):
        k(x).to_dense()
    with pytest.raises(expected, match="columns|dimensionality"):
        k(x, diag=True)
    if dim == 2:
        with pytest.raises(expected, match="columns|dimensionality"):
            k(_x(5, 1, seed=16)).to_dense()


@pytest.mark.parametrize("name,make,dim,fn,psd", CASES, ids=IDS)
def test_acvf_rejects_nonfinite_lags(name, make, dim, fn, psd):
    k = make()
    bad = np.zeros((3, dim))
    bad[1, 0] = np.nan
    with pytest.raises(ValueError, match="lags"):
        k.acvf(bad)
    with pytest.raises(ValueError, match="lags"):
        k.acvf(torch.as_tensor(bad))


@pytest.mark.parametrize("name,make,dim,fn,psd", CASES, ids=IDS)
def test_acvf_and_psd_reject_lags_of_wrong_dimension(name, make, dim, fn, psd):
    """kernel.acvf / kernel.psd take arrays of shape (..., D) with D = the kernel's dimension,
    like forward does; lags with another D are an error, not a silently different ACVF."""
    k = make()
    with pytest.raises(ValueError, match="lags"):
        k.acvf(np.zeros((3, dim + 1)))
    with pytest.raises(ValueError, match="lags"):
        k.acvf(torch.zeros(3, dim + 1, dtype=F64))
    if psd is not None:
        with pytest.raises(ValueError, match="freqs"):
            k.psd(np.zeros((3, dim + 1)))


def test_constructor_does_not_alias_caller_arrays():
    """The kernel must own its parameters: training it must not write into the arrays the
    caller passed to the constructor (nor may the caller's later edits change the kernel)."""
    params = _c(SM2)
    originals = _c(SM2)
    sm = K.SpectralMixtureKernel(2, dim=2, **params)
    x = _x(20, 2, seed=17)
    opt = torch.optim.Adam(sm.parameters(), lr=0.5)
    sm(x).to_dense().sum().backward()
    opt.step()
    assert not torch.equal(sm.means.detach(), torch.as_tensor(originals["means"]))
    for key in ("weights", "means", "variances"):
        np.testing.assert_array_equal(params[key], originals[key], err_msg=key)
    means_t = torch.as_tensor(originals["means"]).clone()
    sm = K.SpectralMixtureKernel(2, dim=2, means=means_t)
    means_t += 1.0
    np.testing.assert_array_equal(_np(sm.means), originals["means"])
    rot = _c(ROT)
    k = K.RotatedExponentialKernel(**rot)
    opt = torch.optim.Adam(k.parameters(), lr=0.5)
    k(x).to_dense().sum().backward()
    opt.step()
    np.testing.assert_array_equal(rot["lengthscales"], ROT["lengthscales"])


# --------------------------------------------------------------------------- repr

def test_repr_is_informative():
    r = repr(K.RotatedExponentialKernel(variance=2.0, lengthscales=(5.0, 1.0), angle=0.3))
    assert r.startswith("RotatedExponentialKernel(")
    for s in ("variance=2.0", "lengthscales=[5.0, 1.0]", "angle=0.3"):
        assert s in r
    r = repr(K.SpectralMixtureKernel(2, dim=2, **_c(SM2)))
    assert r.startswith("SpectralMixtureKernel(")
    for s in ("weights=", "means=", "variances=", "0.3", "0.7"):
        assert s in r
    r = repr(K.MaternKernel(nu=1.5, dim=2, variance=4.0, lengthscale=0.25))
    assert r.startswith("MaternKernel(")
    for s in ("nu=1.5", "dim=2", "variance=4.0", "lengthscale=0.25"):
        assert s in r
    assert r.count("(") == r.count(")")
    r = repr(K.AdditiveKernel(K.MaternKernel(), K.SpectralMixtureKernel(1)))
    assert r.startswith("AdditiveKernel(kernel_x=MaternKernel(")
    assert "kernel_y=SpectralMixtureKernel(" in r
