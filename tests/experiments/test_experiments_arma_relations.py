"""Quick tests of roughgp.experiments.arma_relations (section 2.3, eq 12-17; figure 1)."""

import math

import numpy as np

from roughgp.experiments import arma_relations


def test_ma_finite_has_no_weights_beyond_q():
    r = arma_relations.ma_finite((0.5, -0.3, 0.2), nlags=10)
    assert r.weights.shape == r.acvf.shape == (10,)
    assert r.weights_beyond_q == 0 and r.acvf_beyond_q == 0 and r.gap < 1e-14


def test_arma_truncation_converges():
    r = arma_relations.arma_truncation(truncations=(10, 20, 40, 80))
    assert r.errors == sorted(r.errors, reverse=True) and r.errors[-1] < 1e-12
    assert r.weights.shape == (30,)


def test_sampled_gp_is_arma():
    r = arma_relations.sampled_gp_as_arma(lengthscale=5.0, nlags=200)
    assert r.gap_ou < 1e-13 * r.variance and r.gap_m32 < 1e-12 * r.variance
    assert np.isclose(r.ar1[0][0], math.exp(-1 / 5.0))
    long = arma_relations.sampled_gp_as_arma(lengthscale=500.0, nlags=200)
    assert long.gap_ou < 1e-13 * long.variance          # an exact AR(1) at any length


def test_negative_ar1_is_refused():
    r = arma_relations.negative_ar1(-0.6)
    assert r.alternates and r.refusal
    assert not arma_relations.negative_ar1(0.6).alternates


def test_feature_maps():
    r = arma_relations.feature_maps(steps=(0.5, 0.25))
    assert max(r.gaussian_errors) < 1e-12
    assert abs(r.exponential_errors[0] / r.exponential_errors[1] - 2) < 0.1
    assert r.ar1_gap < 1e-12


def test_figure1_ridge():
    r = arma_relations.figure1_ridge()
    assert abs(r.slowest_deg - 30.0) <= 0.1
    assert np.allclose([r.along, r.across], math.exp(-1), atol=1e-12)
