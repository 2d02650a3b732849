"""Quick tests of roughgp.experiments.small_claims (eq 5, long correlation, non-Gaussian ACVF)."""

import numpy as np
import pytest

from roughgp.experiments import small_claims
from roughgp.gp.kernels import MaternKernel


def test_kernel_duality_table_meets_eq5():
    table = small_claims.kernel_duality_table(full=False, n_1d=2 ** 13 + 1)
    assert set(small_claims.SMOOTH) <= set(table.errors)
    assert table.n_2d == 1025
    assert table.forward < 1e-4 and table.inverse < 1e-10
    measured = table.errors["exponential (Matérn 1/2)"]["lag0_deficit"]
    assert measured == pytest.approx(table.predicted_deficit, rel=1e-3)
    lower, upper = table.fig1_deficit_bounds
    assert lower <= table.errors_fig1["lag0_deficit"] <= upper


def test_long_correlation_small():
    result = small_claims.long_correlation(n_lags=200, orders=(2, 8, 32), n_grid=400,
                                           lengthscale=100.0)
    assert result.yule_walker_gap < 1e-9
    assert result.ar1_gap < 1e-12 and result.circulant_clipped == 0.0
    assert result.filter_at_wrap > 1.5 * result.true_at_wrap
    matern = result.fit_error["Matern-3/2"]
    assert matern[0] > matern[1] > matern[2]
    assert min(result.fit_error["periodic"]) > 0.05
    assert result.fits["periodic", 8].shape == (201,)


def test_non_gaussian_acvf_small():
    kernel = MaternKernel(nu=0.5, dim=2, variance=1.0, lengthscale=4.0)
    targets = {"Gaussian": (0.0, 3.0), "plateau": (-1.5, 6.0)}
    result = small_claims.non_gaussian_acvf(targets=targets, kernel=kernel, shape=(96, 96),
                                            seed=2, n_samples=3, max_lag=4)
    again = small_claims.non_gaussian_acvf(targets={"plateau": (-1.5, 6.0)}, kernel=kernel,
                                           shape=(96, 96), seed=2, n_samples=3, max_lag=4)
    assert result.draws["plateau"].shape == (3, 96, 96)
    np.testing.assert_array_equal(result.draws["plateau"], again.draws["plateau"])
    assert "Gaussian" not in result.naive and "Gaussian" not in result.rms
    assert result.target_acvf.shape == (9, 9) and result.target_acvf[4, 4] == 1.0
    assert result.moments["plateau"]["Sq"].target == 1.0
    assert result.moments["plateau"]["Ssk"].mean < -0.5          # clearly skewed heights
    rms = result.rms["plateau"]
    assert rms["without vs r(0) g(rho)"] < rms["without"]
    assert result.quantile > 10                                  # t_0.999 with 2 dof
