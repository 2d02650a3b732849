"""roughgp.experiments.error_readings: section 3.1's readings and their expected errors (a small
grid; the ledger's check sec3.1-error-values runs the paper's)."""

import math

import numpy as np
import pytest

from roughgp.experiments import error_readings as er
from roughgp.models import surfaces
from roughgp.sampling import diagnostics
from roughgp.sampling.grid_sampler import grid_covariance

SMALL = surfaces.GrooveParameters(variance=2.0, lengthscales=(6.0, 2.0), angle=math.pi / 6)
SHAPE = (5, 6)


def test_the_stated_reading_equals_the_dense_expectation():
    dense = diagnostics.expected_covariance_error(grid_covariance(SMALL.kernel(), SHAPE), 50)
    assert er.expected_error(SMALL, SHAPE, 50) == pytest.approx(dense, rel=1e-12)


@pytest.mark.parametrize("case", [
    {"estimator": "ddof=0"}, {"estimator": "known mean"},
    {"noise_variance": 1.0}, {"noise_variance": 1.0, "noisy_target": False},
    {"spacing": 0.5}])
def test_each_reading_matches_a_monte_carlo_of_it(case):
    """The folded-normal expectation against 400 experiments of 30 exact draws each."""
    n, repeats, rng = 30, 400, np.random.default_rng(5)
    spacing = case.get("spacing", 1.0)
    r = grid_covariance(SMALL.kernel(), SHAPE, spacing=spacing)
    noise = case.get("noise_variance", 0.0)
    drawn = r + noise * np.eye(r.shape[0])
    target = drawn if case.get("noisy_target", True) else r
    root = np.linalg.cholesky(drawn)
    errors = []
    for _ in range(repeats):
        x = rng.standard_normal((n, r.shape[0])) @ root.T
        if case.get("estimator") == "known mean":
            s = x.T @ x / n
        else:
            x = x - x.mean(axis=0)
            s = x.T @ x / (n if case.get("estimator") == "ddof=0" else n - 1)
        errors.append(np.abs(s - target).mean())
    expected = er.expected_error(SMALL, SHAPE, n, **case)
    assert abs(np.mean(errors) - expected) < 0.05 * expected


def test_the_readings_list_starts_as_stated_and_names_each_change():
    table = er.readings(SMALL, SHAPE, 50)
    assert table[0].label.startswith("as stated")
    assert table[0].expected == pytest.approx(er.expected_error(SMALL, SHAPE, 50))
    assert len({r.label for r in table}) == len(table)
    assert {r.estimator for r in table} == set(er.ESTIMATORS)
    by = {r.label: r for r in table}
    assert by["1000 draws"].expected == pytest.approx(
        table[0].expected * math.sqrt(49 / 999), rel=1e-9)
    assert by["sigma_k^2 = 1"].expected == pytest.approx(table[0].expected / SMALL.variance)
    with pytest.raises(ValueError, match="estimator must be one of"):
        er.expected_error(SMALL, SHAPE, 50, estimator="ddof=2")
