"""The non-stationary eq 18 surface: Paciorek's covariance and the K-kernel blended sampler."""

from __future__ import annotations

import math

import numpy as np
import pytest

from roughgp.common.grid import coordinates
from roughgp.gp.acvf import matern, rotate
from roughgp.gp.numpy_kernels import RotatedExponentialACVF
from roughgp.models import nonstationary as ns
from roughgp.models.nonstationary import ParameterField, paciorek_covariance

CONSTANT = ParameterField(variance=2.0, lambda_a=5.0, lambda_b=2.0, angle=math.pi / 6)
EQ18 = RotatedExponentialACVF(2.0, (5.0, 2.0), math.pi / 6)
SPACING = (1.0, 0.8)  # (dy, dx)


def _ramp(low, high, width=23.0):
    return lambda x, y: low + (high - low) * np.clip(x / width, 0, 1)


#: lengths and angle that change left to right, the variance constant
VARYING = ParameterField(variance=1.5, lambda_a=_ramp(2.0, 7.0), lambda_b=_ramp(1.5, 3.0),
                         angle=_ramp(0.0, math.pi / 3))


def _grid_lags(shape, spacing):
    points = coordinates(shape, spacing)
    return points, points[:, :, None, None, :] - points[None, None]


def test_constant_parameters_give_eq18_covariance():
    points, lags = _grid_lags((6, 7), SPACING)
    covariance = paciorek_covariance(points, points, CONSTANT)
    expected = EQ18.acvf(-lags)
    assert covariance.shape == (6, 7, 6, 7)
    np.testing.assert_allclose(covariance, expected, rtol=1e-12, atol=0)


def test_constant_parameters_squared_exponential_is_the_rotated_gaussian():
    points, lags = _grid_lags((5, 6), SPACING)
    covariance = paciorek_covariance(points, points, CONSTANT, correlation="squared_exponential")
    scaled = rotate(lags, math.pi / 6) / np.array([5.0, 2.0])
    expected = matern(scaled, 2.0, 1 / math.sqrt(2), math.inf)  # 2 exp(-|L^-1 T tau|^2)
    np.testing.assert_allclose(covariance, expected, rtol=1e-12, atol=0)


def test_noise_enters_only_where_points_coincide():
    field = ParameterField(variance=1.0, lambda_a=3.0, lambda_b=3.0, noise_variance=0.25)
    points = coordinates((3, 3), 1.0).reshape(-1, 2)
    latent = paciorek_covariance(points, points, field)
    noisy = paciorek_covariance(points, points, field, noise=True)
    np.testing.assert_allclose(noisy - latent, 0.25 * np.eye(9), atol=1e-15)


@pytest.mark.parametrize("correlation", ns.CORRELATIONS)
def test_paciorek_matrix_is_symmetric_positive_semidefinite(correlation):
    points = coordinates((10, 10), 1.0).reshape(-1, 2)
    field = ParameterField(variance=lambda x, y: 1 + 0.3 * x, lambda_a=_ramp(1.0, 6.0, 9.0),
                           lambda_b=lambda x, y: 1.0 + 0.1 * y, angle=lambda x, y: 0.2 * y)
    covariance = paciorek_covariance(points, points, field, correlation=correlation)
    np.testing.assert_allclose(covariance, covariance.T, rtol=1e-13, atol=0)
    assert np.linalg.eigvalsh(covariance).min() > -1e-10 * np.trace(covariance)
    np.testing.assert_allclose(np.diag(covariance), 1 + 0.3 * points[:, 0], rtol=1e-13)


def test_constant_field_blend_is_exactly_eq18_on_the_grid():
    plan = ns.blend_plan((9, 8), SPACING, CONSTANT, n_kernels=4)
    assert len(plan.anchors) == 1  # one distinct parameter set: one kernel, whatever K
    points, lags = _grid_lags((9, 8), SPACING)
    expected = EQ18.acvf(lags).reshape(72, 72)
    np.testing.assert_allclose(ns.blend_covariance(plan), expected, rtol=0, atol=1e-10)


def test_blend_keeps_the_local_variance_and_approaches_paciorek():
    points = coordinates((12, 24), 1.0)
    exact = paciorek_covariance(points, points, VARYING).reshape(288, 288)
    errors = []
    for k in (1, 4):
        blend = ns.blend_covariance(ns.blend_plan((12, 24), 1.0, VARYING, n_kernels=k))
        np.testing.assert_allclose(np.diag(blend), 1.5, rtol=1e-10)
        errors.append(np.linalg.norm(blend - exact) / np.linalg.norm(exact))
    assert errors[1] < errors[0] / 3 and errors[1] < 0.1, errors


def test_sampler_matches_eq18_covariance_within_monte_carlo_error():
    """Per lag, the grid average of z(x) z(x + lag) in each draw is one number; over 300
    independent draws its mean must be within 4 standard errors of eq 18 at that lag."""
    shape, n = (24, 24), 300
    z = ns.sample_nonstationary(shape, SPACING, CONSTANT, n_kernels=3, n_samples=n, seed=7,
                                latent=True)
    for dy, dx in ((0, 0), (0, 1), (0, 3), (1, 0), (3, 0), (2, 2), (2, -2)):
        a = z[:, :shape[0] - dy, max(0, -dx):shape[1] - max(0, dx)]
        b = z[:, dy:, max(0, dx):shape[1] + min(0, dx)]
        per_draw = (a * b).mean(axis=(1, 2))
        se = per_draw.std(ddof=1) / math.sqrt(n)
        expected = EQ18.acvf(np.array([dx * SPACING[1], dy * SPACING[0]]))
        assert abs(per_draw.mean() - expected) < 4 * se, (dy, dx, per_draw.mean(), expected, se)


def _left_right_variances(z):
    half = z.shape[-1] // 2
    return (z[..., :half] ** 2).mean(axis=(1, 2)), (z[..., half:] ** 2).mean(axis=(1, 2))


def test_stationary_field_comes_back_stationary():
    left, right = _left_right_variances(ns.sample_nonstationary(
        (16, 32), 1.0, ParameterField(1.0, 3.0, 2.0, 0.4, noise_variance=0.5), n_samples=300,
        seed=3))
    difference = left - right
    assert abs(difference.mean()) < 4 * difference.std(ddof=1) / math.sqrt(len(difference))
    assert left.mean() == pytest.approx(1.5, rel=0.05)


def test_variance_changing_left_to_right_gives_the_right_ratio():
    field = ParameterField(variance=lambda x, y: np.where(x < 16, 1.0, 4.0), lambda_a=2.0,
                           lambda_b=2.0)
    left, right = _left_right_variances(ns.sample_nonstationary(
        (16, 32), 1.0, field, n_kernels=2, n_samples=300, seed=4, latent=True))
    assert left.mean() == pytest.approx(1.0, rel=0.08)
    assert right.mean() / left.mean() == pytest.approx(4.0, rel=0.1)


def test_varying_lengths_keep_variance_in_the_draws():
    z = ns.sample_nonstationary((12, 24), 1.0, VARYING, n_kernels=4, n_samples=200, seed=5,
                                latent=True)
    left, right = _left_right_variances(z)
    assert left.mean() == pytest.approx(1.5, rel=0.1)
    assert right.mean() == pytest.approx(1.5, rel=0.15)


def test_seeds_reproduce_and_differ():
    one = ns.sample_nonstationary((8, 10), 1.0, VARYING, n_kernels=2, seed=11)
    assert one.shape == (1, 8, 10)
    np.testing.assert_array_equal(one, ns.sample_nonstationary((8, 10), 1.0, VARYING,
                                                               n_kernels=2, seed=11))
    assert not np.allclose(one, ns.sample_nonstationary((8, 10), 1.0, VARYING, n_kernels=2,
                                                        seed=12))


@pytest.mark.parametrize("kwargs, name", [
    (dict(lambda_a=-1.0), "lambda_a"),
    (dict(lambda_b=0.0), "lambda_b"),
    (dict(variance=np.array([[1.0, -2.0]])), "variance"),
    (dict(angle=math.nan), "angle"),
    (dict(noise_variance=-0.1), "noise_variance"),
])
def test_bad_constants_raise_naming_the_parameter(kwargs, name):
    with pytest.raises(ValueError, match=name):
        ParameterField(**kwargs)


def test_bad_callables_shapes_and_options_raise_naming_the_parameter():
    points = coordinates((4, 4), 1.0)
    with pytest.raises(ValueError, match="lambda_b.*> 0"):
        ParameterField(lambda_b=lambda x, y: 1.0 - x).at(points)
    with pytest.raises(ValueError, match="variance.*shape"):
        ParameterField(variance=np.ones((3, 3))).at(points)
    with pytest.raises(ValueError, match="n_kernels"):
        ns.sample_nonstationary((4, 4), 1.0, CONSTANT, n_kernels=0)
    with pytest.raises(ValueError, match="correlation"):
        paciorek_covariance(points, points, CONSTANT, correlation="gaussian")
    with pytest.raises(ValueError, match="seed"):
        ns.sample_nonstationary((4, 4), 1.0, CONSTANT, seed=-1)
