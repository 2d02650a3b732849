"""The GP as a continuous moving average (eq 16, 17): feature maps, quadrature, draws."""

from __future__ import annotations

import math

import numpy as np
import pytest

from roughgp.models import moving_average as ma


@pytest.mark.parametrize("step", [1.0, 0.3, 0.05])
def test_gaussian_feature_map_gives_the_squared_exponential_at_any_step(step):
    # beta is smooth and decays fast: the Riemann sum of eq 17 is exact to rounding
    fm = ma.gaussian_feature_map(2.0, 3.0)
    lags = np.arange(30) * step
    np.testing.assert_allclose(ma.feature_map_acvf(fm, 30, step), fm.kernel(lags),
                               rtol=0, atol=1e-13)
    np.testing.assert_allclose(fm.kernel(lags), 2.0 * np.exp(-lags**2 / 18.0), rtol=1e-14)


def test_exponential_feature_map_sum_is_an_ar1_acvf_converging_at_first_order():
    variance, lam = 2.0, 3.0
    fm = ma.exponential_feature_map(variance, lam)
    errors = []
    for step in (0.4, 0.2, 0.1):
        a = math.exp(-step / lam)
        c2 = 2 * variance / lam
        k = np.arange(25)
        exact_sum = c2 * step * a**k / (1 - a**2)            # geometric series, closed form
        numeric = ma.feature_map_acvf(fm, 25, step)
        np.testing.assert_allclose(numeric, exact_sum, rtol=1e-12)
        errors.append(abs(numeric[0] - variance))
    # the jump of beta at 0 makes the rectangle rule first order: halving h halves the error
    assert errors[0] / errors[1] == pytest.approx(2.0, rel=0.05)
    assert errors[1] / errors[2] == pytest.approx(2.0, rel=0.05)


def test_feature_map_acvf_pads_lags_beyond_the_support_with_zero():
    fm = ma.gaussian_feature_map(1.0, 0.5)
    values = ma.feature_map_acvf(fm, 400, 0.1)
    assert values.shape == (400,) and values[-1] == 0.0


@pytest.mark.parametrize("factory", [ma.gaussian_feature_map, ma.exponential_feature_map])
def test_draws_have_the_acvf_of_the_discretised_sum(factory):
    fm, step = factory(1.5, 2.0), 0.25
    z = ma.moving_average_sample(fm, 512, step, n_samples=400, seed=4)
    assert z.shape == (400, 512)
    expected = ma.feature_map_acvf(fm, 6, step)
    for k in range(6):
        products = (z[:, :512 - k] * z[:, k:]).mean(axis=1)   # one estimate per draw
        se = products.std(ddof=1) / math.sqrt(len(products))
        assert abs(products.mean() - expected[k]) < 5 * se


def test_same_seed_same_draw():
    fm = ma.exponential_feature_map(1.0, 2.0)
    a = ma.moving_average_sample(fm, 50, 0.5, n_samples=2, seed=7)
    np.testing.assert_array_equal(a, ma.moving_average_sample(fm, 50, 0.5, n_samples=2, seed=7))
    assert not np.allclose(a, ma.moving_average_sample(fm, 50, 0.5, n_samples=2, seed=8))


@pytest.mark.parametrize("call, name", [
    (lambda: ma.gaussian_feature_map(-1.0, 1.0), "variance"),
    (lambda: ma.exponential_feature_map(1.0, 0.0), "lengthscale"),
    (lambda: ma.feature_map_acvf(ma.gaussian_feature_map(1.0, 1.0), 0, 0.1), "n_lags"),
    (lambda: ma.feature_map_acvf(ma.gaussian_feature_map(1.0, 1.0), 5, -0.1), "step"),
    (lambda: ma.moving_average_sample(ma.gaussian_feature_map(1.0, 1.0), 0, 0.1), "n"),
    (lambda: ma.moving_average_sample(ma.gaussian_feature_map(1.0, 1.0), 5, 0.1,
                                      n_samples=1.5), "n_samples"),
    (lambda: ma.moving_average_sample(ma.gaussian_feature_map(1.0, 1.0), 5, 0.1, seed=-1),
     "seed"),
])
def test_errors_name_the_parameter(call, name):
    with pytest.raises(ValueError, match=name):
        call()
