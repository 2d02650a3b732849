"""The numpy kernels (roughgp.gp.numpy_kernels) against their GPyTorch twins: the same ACVF,
the same draws from the same seed (to rounding), and clear errors for bad hyperparameters."""

from __future__ import annotations

import math

import numpy as np
import pytest

from roughgp.gp.kernels import MaternKernel, RotatedExponentialKernel
from roughgp.gp.numpy_kernels import MaternACVF, RotatedExponentialACVF
from roughgp.models import surfaces
from roughgp.sampling import sample_grid

LAGS = np.random.default_rng(0).normal(scale=40.0, size=(50, 2))


@pytest.mark.parametrize("variance, lengthscales, angle",
                         [(45.0, (500.0, 30.0), math.pi / 4), (0.2, (5.0, 3.0), -1.0)])
def test_rotated_exponential_is_the_gpytorch_kernels(variance, lengthscales, angle):
    ours = RotatedExponentialACVF(variance, lengthscales, angle)
    theirs = RotatedExponentialKernel(variance, lengthscales, angle)
    np.testing.assert_allclose(ours.acvf(LAGS), theirs.acvf(LAGS), rtol=1e-13)
    np.testing.assert_allclose(ours.psd(LAGS / 1e3), theirs.psd(LAGS / 1e3), rtol=1e-13)


@pytest.mark.parametrize("nu, dim", [(0.5, 1), (0.5, 2), (2.5, 2), (math.inf, 1)])
def test_matern_is_the_gpytorch_kernels(nu, dim):
    lags = LAGS[:, :dim]
    ours = MaternACVF(variance=0.3, lengthscale=7.0, nu=nu, dim=dim)
    theirs = MaternKernel(nu=nu, dim=dim, variance=0.3, lengthscale=7.0)
    np.testing.assert_allclose(ours.acvf(lags), theirs.acvf(lags), rtol=1e-13)


@pytest.mark.parametrize("method, shape", [("cholesky", (12, 14)), ("circulant", (20, 24))])
def test_a_seed_draws_what_the_gpytorch_kernel_drew(method, shape):
    """The ground surfaces of a honed surface, drawn from the numpy kernel, are those the
    GPyTorch kernel gave before, to rounding (its softplus moves 30.0 to 29.999999999999908);
    another seed gives another surface (the comparison can fail)."""
    for step in surfaces.FIGURE_3:
        for mirrored in (False, True):
            new = sample_grid(step.covariance(mirrored), shape, method=method, seed=5)
            old = sample_grid(step.kernel(mirrored), shape, method=method, seed=5)
            np.testing.assert_allclose(new, old, rtol=1e-9, atol=1e-9 * np.abs(old).max())
            other = sample_grid(step.kernel(mirrored), shape, method=method, seed=6)
            assert np.abs(new - other).max() > 0.1 * np.abs(old).max()


@pytest.mark.parametrize("make, name", [
    (lambda: RotatedExponentialACVF(0.0, (1.0, 1.0), 0.0), "variance"),
    (lambda: RotatedExponentialACVF(1.0, (1.0, -2.0), 0.0), "lengthscales"),
    (lambda: RotatedExponentialACVF(1.0, (1.0, 2.0, 3.0), 0.0), "lengthscales"),
    (lambda: RotatedExponentialACVF(1.0, (1.0, 2.0), math.nan), "angle"),
    (lambda: MaternACVF(variance=1.0, lengthscale=math.inf), "lengthscale"),
    (lambda: MaternACVF(variance=1.0, lengthscale=1.0, nu=1.0), "nu"),
    (lambda: MaternACVF(variance=1.0, lengthscale=1.0, dim=0), "dim"),
    (lambda: MaternACVF(variance=1.0, lengthscale=1.0, dim=2).acvf(np.zeros((3, 1))), "2-D"),
])
def test_bad_hyperparameters_are_named(make, name):
    with pytest.raises(ValueError, match=name):
        make()
