"""Tests of roughgp.targets.closed_form: ground surfaces with prescribed ISO 25178-2 Sq, Sal,
Str, Std.

Surfaces are at most 512 x 512 (a quarter of a second each); the file runs in about 10 s.
"""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

from roughgp import targets as T
from roughgp.models import surfaces

NOISE = 1.0 / 11  # the paper's ratio sigma^2 / sigma_k^2 = 1/10 for Sq = 1


# ------------------------------------------------------------------ the closed form

@pytest.mark.parametrize("Sq, Sal, Str, Std, noise", [
    (1.0, 8.0, 0.3, 30.0, 0.0),
    (1.2, 40.0, 0.2, -45.0, 0.131),
    (3.5, 2.5, 1.0, 89.0, 1.0),       # isotropic
    (2.0, 100.0, 0.01, -89.9, 3.19),  # close to the limit Sq^2 > 1.25 noise
])
def test_round_trip_targets_hyperparameters_targets(Sq, Sal, Str, Std, noise):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # Sal = 2.5 is under three spacings
        h = T.hyperparameters_for(Sq, Sal, Str, Std, noise_variance=noise)
        back = T.predicted_targets(h)
        again = T.hyperparameters_for(**back.as_dict(), noise_variance=noise)
    assert h.lengthscales[0] >= h.lengthscales[1] > 0 and h.variance > 0
    assert h.noise_variance == noise
    for name, value in zip(T.TARGET_NAMES, (Sq, Sal, Str, Std)):
        assert getattr(back, name) == pytest.approx(value, rel=1e-12, abs=1e-12), name
    assert again.variance == pytest.approx(h.variance, rel=1e-12)
    np.testing.assert_allclose(again.lengthscales, h.lengthscales, rtol=1e-12)
    assert again.angle == pytest.approx(h.angle, abs=1e-12)


def test_round_trip_hyperparameters_targets_hyperparameters_figure_2():
    """Figure 2's hyperparameters: the predictions of the ground chapter, and back."""
    fig2 = surfaces.FIGURE_2
    h = T.GroundHyperparameters(fig2.variance, fig2.lengthscales, fig2.angle, 1.0)
    t = T.predicted_targets(h)
    assert t.Sq == pytest.approx(math.sqrt(11))
    assert t.Sal == pytest.approx(5 * math.log(50 / 11))  # 7.57, the ground chapter's value
    assert t.Str == pytest.approx(0.01) and t.Std == pytest.approx(30.0)
    back = T.hyperparameters_for(**t.as_dict(), noise_variance=1.0)
    assert back.groove.variance == pytest.approx(fig2.variance)
    np.testing.assert_allclose(back.groove.lengthscales, fig2.lengthscales, rtol=1e-12)
    assert back.angle == pytest.approx(fig2.angle)
    assert back.ground_kwargs() == {"variance": back.variance, "lengthscales":
                                    back.lengthscales, "angle": back.angle,
                                    "noise_variance": 1.0}


def test_std_is_folded_to_the_convention_of_texture_direction():
    for given, folded in ((120.0, -60.0), (-90.0, 90.0), (270.0, 90.0), (-135.0, 45.0),
                          (30.0, 30.0)):
        h = T.hyperparameters_for(1.0, 8.0, 0.2, given, noise_variance=0.0)
        assert math.degrees(h.angle) == pytest.approx(folded)
        assert T.RoughnessTargets(1.0, 8.0, 0.2, given).Std == pytest.approx(folded)
    # lambda_a < lambda_b: the lay is across the first axis
    h = T.GroundHyperparameters(1.0, (2.0, 20.0), math.radians(10.0), 0.0)
    assert T.predicted_targets(h).Std == pytest.approx(-80.0)


@pytest.mark.parametrize("kwargs, message", [
    (dict(Sq=1.1, noise_variance=1.0), r"Sq must be > sqrt\(5 noise_variance / 4\) = 1.11803"),
    (dict(Sq=math.sqrt(1.25), noise_variance=1.0), r"allowed range: \(1.11803, inf\)"),
    (dict(Sq=0.5, noise_variance=0.8 * 0.25 + 1e-9), r"Sq must be > sqrt"),
    (dict(Sq=0.0, noise_variance=0.0), r"Sq must be > 0 and within \[1e-60, 1e\+60\]"),
    (dict(Sq=1e300), r"Sq must be > 0 and within \[1e-60, 1e\+60\] \(allowed range"),
    (dict(Sq=-1.0), r"Sq must be > 0"),
    (dict(Str=0.0), r"Str must be in \(0, 1\]"),
    (dict(Str=1.0 + 1e-12), r"Str must be in \(0, 1\]"),
    (dict(Str=-0.2), r"Str must be in \(0, 1\]"),
    (dict(Sal=0.0), r"Sal must be > 0 and within \[1e-60, 1e\+60\] \(allowed range"),
    (dict(Sal=1e-300), r"Sal must be > 0 and within"),
    (dict(Sal=-3.0), r"Sal must be > 0"),
    (dict(Sq=math.nan), r"Sq must be finite"),
    (dict(Sal=math.nan), r"Sal must be finite"),
    (dict(Str=math.nan), r"Str must be finite"),
    (dict(Std=math.inf), r"Std must be finite"),
    (dict(Std="north"), r"Std must be a number"),
    (dict(noise_variance=-0.1), r"noise_variance must be >= 0"),
    (dict(noise_variance=math.nan), r"noise_variance must be finite"),
    (dict(spacing=0.0), r"spacing"),
])
def test_bad_targets_name_the_parameter_and_range(kwargs, message):
    args = dict(Sq=1.0, Sal=8.0, Str=0.3, Std=30.0, noise_variance=0.1) | kwargs
    with pytest.raises(ValueError, match=message):
        T.hyperparameters_for(**args)


def test_the_limit_on_sq_is_where_the_acf_starts_at_0_2():
    noise = 1.0
    just_above = math.sqrt(1.25 * noise) * (1 + 1e-6)
    with pytest.warns(UserWarning, match="grid spacings"):
        h = T.hyperparameters_for(just_above, 1.0, 0.5, 0.0, noise_variance=noise)
    assert h.variance / (h.variance + noise) == pytest.approx(0.2, rel=1e-5)
    assert h.lengthscales[1] > 1e4  # ln(5c) -> 0: the lengthscale needed diverges
    with pytest.raises(ValueError, match="Sal and Str are undefined"):
        T.predicted_targets(T.GroundHyperparameters(0.2, (5.0, 1.0), 0.0, 1.0))


def test_as_targets_names_missing_and_unknown_keys():
    assert T.as_targets({"Sq": 1, "Sal": 2, "Str": 0.5, "Std": 10}).Sal == 2.0
    with pytest.raises(ValueError, match="missing target Std"):
        T.as_targets({"Sq": 1, "Sal": 2, "Str": 0.5})
    with pytest.raises(ValueError, match="unknown target 'Sa'"):
        T.as_targets({"Sq": 1, "Sal": 2, "Str": 0.5, "Std": 10, "Sa": 1})
    with pytest.raises(ValueError, match="mapping"):
        T.as_targets([1, 2, 0.5, 10])


def test_an_unresolved_sal_warns():
    with pytest.warns(UserWarning, match="under 3 grid spacings"):
        T.hyperparameters_for(1.0, 2.0, 0.5, 0.0, noise_variance=0.0)
    with pytest.warns(UserWarning, match="grid spacings"):
        T.hyperparameters_for(1.0, 8.0, 0.5, 0.0, noise_variance=0.0, spacing=(1.0, 4.0))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        T.hyperparameters_for(1.0, 8.0, 0.5, 0.0, noise_variance=0.0, spacing=2.0)


def test_directions_wrap_at_plus_minus_90():
    assert T.direction_difference(-89.0, 89.0) == pytest.approx(2.0)
    assert T.mean_direction([89.0, -89.0]) == pytest.approx(90.0)
    assert T.mean_direction([10.0, 20.0]) == pytest.approx(15.0, abs=1e-9)
    s = T.summarize({"Sq": [1.0, 3.0], "Sal": [1.0, 1.0], "Str": [0.2, 0.4],
                     "Std": [88.0, -88.0]})
    assert s["Sq"] == pytest.approx((2.0, math.sqrt(2)))
    assert abs(T.direction_difference(s["Std"][0], 90.0)) < 1e-9
    assert s["Std"][1] == pytest.approx(math.sqrt(8))


# ------------------------------------------------------------------ measured surfaces

def test_the_closed_form_is_unbiased_on_a_long_field():
    """Sal = 8, Str = 0.3 on 256 x 256 (15 lambda_a): the mean of 8 surfaces within 4
    standard errors of each target (the per-surface spread is about 14 %)."""
    h = T.hyperparameters_for(1.0, 8.0, 0.3, -20.0, noise_variance=NOISE)
    values = T.achieved_parameters(h, (256, 256), seeds=range(8))
    summary = T.summarize(values)
    for name, target in (("Sq", 1.0), ("Sal", 8.0), ("Str", 0.3)):
        mean, sd = summary[name]
        assert abs(mean - target) <= 4 * sd / math.sqrt(8), (name, mean, sd)
