"""Tests of roughgp.inference.mixture_posterior: relabelling eq 21's components, predictive profiles."""

import math

import numpy as np
import pytest

from roughgp.inference import mixture_posterior as mp


def draws():
    # two draws of a Q = 2 mixture; the second is the first with its labels swapped
    return {"w_1": np.array([4.0, 0.5]), "mu_1": np.array([0.004, 0.001]),
            "v_1": np.array([1e-9, 1e-4]),
            "w_2": np.array([0.5, 4.0]), "mu_2": np.array([0.001, 0.004]),
            "v_2": np.array([1e-4, 1e-9]), "noise_variance": np.array([0.01, 0.02])}


def test_component_count():
    assert mp.component_count(draws()) == 2
    assert mp.component_count({"w_1": 1, "mu_1": 0, "v_1": 1}) == 1
    with pytest.raises(ValueError, match="w_1, mu_1 and v_1"):
        mp.component_count({"w_1": 1, "noise_variance": 1})


@pytest.mark.parametrize("by", ["peak", "weight", "mean"])
def test_relabelling_undoes_a_label_switch(by):
    out = mp.relabel_components(draws(), by=by)
    for name in ("w", "mu", "v"):
        for i in (1, 2):                  # both draws now agree component by component
            assert out[f"{name}_{i}"][0] == out[f"{name}_{i}"][1]
    np.testing.assert_array_equal(out["noise_variance"], [0.01, 0.02])  # copied as is
    first = {"peak": 0.004, "weight": 0.004, "mean": 0.001}[by]
    assert out["mu_1"][0] == first


def test_relabelling_by_peak_differs_from_by_weight():
    # a broad heavy component and a sharp lighter line: weight and peak disagree
    d = {"w_1": np.array([3.0]), "mu_1": np.array([0.0]), "v_1": np.array([1e-2]),
         "w_2": np.array([1.0]), "mu_2": np.array([0.004]), "v_2": np.array([1e-8])}
    assert mp.relabel_components(d, by="weight")["mu_1"][0] == 0.0
    assert mp.relabel_components(d, by="peak")["mu_1"][0] == 0.004


def test_relabelling_refuses_an_unknown_order_and_leaves_its_input():
    d = draws()
    with pytest.raises(ValueError, match="by must be one of"):
        mp.relabel_components(d, by="frequency")
    mp.relabel_components(d)
    assert d["w_1"][1] == 0.5


def test_predictive_profiles_have_the_acvf_of_the_draw():
    # one hyperparameter draw: the profiles' lag covariances are eq 21 plus the noise
    d = {"w_1": np.array([2.0]), "mu_1": np.array([0.1]), "v_1": np.array([1e-3]),
         "noise_variance": np.array([0.5])}
    prof = mp.predictive_profiles(d, 8, spacing=2.0, n_draws=20000, seed=4)
    assert prof.shape == (20000, 8)
    lags = 2.0 * np.arange(4)
    expected = 2.0 * np.cos(2 * math.pi * 0.1 * lags) * np.exp(-2 * math.pi ** 2 * 1e-3 * lags ** 2)
    expected[0] += 0.5
    empirical = [np.mean(prof[:, 0] * prof[:, k]) for k in range(4)]
    # standard error of a product moment with variance <= 2.5^2: 2.5^2 * sqrt(2 / 20000)
    np.testing.assert_allclose(empirical, expected, atol=4 * 2.5 ** 2 * math.sqrt(2 / 20000))
    no_noise = mp.predictive_profiles(d, 8, spacing=2.0, n_draws=20000, seed=4, noise=False)
    assert np.var(no_noise[:, 0]) == pytest.approx(2.0, rel=0.05)


def test_predictive_profiles_are_seeded_and_checked():
    a = mp.predictive_profiles(draws(), 64, 4.0, n_draws=3, seed=11)
    b = mp.predictive_profiles(draws(), 64, 4.0, n_draws=3, seed=11)
    np.testing.assert_array_equal(a, b)
    assert not np.array_equal(a, mp.predictive_profiles(draws(), 64, 4.0, n_draws=3, seed=12))
    assert np.all(np.isfinite(a))
    with pytest.raises(ValueError, match="n_points must be <= 8192"):
        mp.predictive_profiles(draws(), 10_000)
    with pytest.raises(ValueError, match="n_points"):
        mp.predictive_profiles(draws(), 1)
    with pytest.raises(ValueError, match="spacing"):
        mp.predictive_profiles(draws(), 16, spacing=0.0)
    with pytest.raises(ValueError, match="n_draws"):
        mp.predictive_profiles(draws(), 16, n_draws=0)
    d = draws()
    del d["noise_variance"]
    with pytest.raises(ValueError, match="noise_variance"):
        mp.predictive_profiles(d, 16)
    assert mp.predictive_profiles(d, 16, n_draws=1, noise=False, seed=0).shape == (1, 16)
