"""Tests of roughgp.targets.calibration: surfaces drawn with prescribed ISO 25178-2 Sq, Sal, Str,
Std, and the calibration of the closed form on a finite field.

Surfaces are at most 512 x 512 (a quarter of a second each).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from roughgp import targets as T
from roughgp.models import surfaces
from roughgp.targets import calibration as P

NOISE = 1.0 / 11  # the paper's ratio sigma^2 / sigma_k^2 = 1/10 for Sq = 1


# ------------------------------------------------------------------ simulated surfaces

def test_a_simulated_surface_hits_sq_and_std():
    """512 x 512, Sal = 8, Str = 0.1 (lambda_a = 53: ten groove lengths across the field):
    Sq within 4 predicted sd, Std within 2 degrees (its spread over 20 seeds is about 1
    degree here; at Str = 0.3 it is about 4 degrees, see the chapter)."""
    targets = T.RoughnessTargets(Sq=1.0, Sal=8.0, Str=0.1, Std=30.0)
    z, h = P.simulate_with_targets(targets, (512, 512), seed=3, noise_variance=NOISE)
    assert z.shape == (512, 512) and np.all(np.isfinite(z))
    measured = T.measure(z)
    mean, sd = T.sq_prediction(h, (512, 512))
    assert abs(mean - 1.0) < 0.01 and 0 < sd < 0.05
    assert abs(measured["Sq"] - mean) <= 4 * sd
    assert abs(T.direction_difference(measured["Std"], 30.0)) <= 2.0
    assert abs(measured["Sal"] / 8.0 - 1) < 0.3 and abs(measured["Str"] / 0.1 - 1) < 0.3


def test_a_folded_direction_is_drawn_where_texture_direction_reads_it():
    z, _ = P.simulate_with_targets({"Sq": 2.0, "Sal": 4.0, "Str": 0.1, "Std": 125.0},
                                   (256, 256), seed=0, spacing=1.0, noise_variance=0.0)
    assert abs(T.direction_difference(T.measure(z)["Std"], -55.0)) <= 2.0


def test_simulate_is_deterministic_by_seed():
    t = {"Sq": 0.5, "Sal": 5.0, "Str": 0.5, "Std": 45.0}
    a, ha = P.simulate_with_targets(t, (48, 64), seed=11, noise_variance=0.01)
    b, hb = P.simulate_with_targets(t, (48, 64), seed=11, noise_variance=0.01)
    c, _ = P.simulate_with_targets(t, (48, 64), seed=12, noise_variance=0.01)
    assert np.array_equal(a, b) and ha == hb
    assert not np.allclose(a, c)
    assert ha == T.hyperparameters_for(**t, noise_variance=0.01)
    np.testing.assert_array_equal(
        a, surfaces.ground((48, 64), **ha.ground_kwargs(), seed=11, method="auto"))
    with pytest.raises(ValueError, match="shape must be"):
        P.simulate_with_targets(t, (64,), seed=1)


def test_a_short_field_warns():
    t = {"Sq": 1.0, "Sal": 8.0, "Str": 0.1, "Std": 0.0}  # lambda_a = 50
    h = T.hyperparameters_for(**t, noise_variance=0.0)
    assert T.groove_lengths(h, (64, 256)) == pytest.approx(64 / h.lengthscales[0])
    assert T.groove_lengths(h, (64, 256), spacing=(8.0, 1.0)) == pytest.approx(
        256 / h.lengthscales[0])
    assert T.field_warning(h, (512, 512)) is None
    with pytest.warns(UserWarning, match=r"only 1.29 correlation lengths .* at least 248"):
        P.simulate_with_targets(t, (64, 256), seed=0, noise_variance=0.0)


# ------------------------------------------------------------------ calibration

def test_calibration_removes_the_bias_of_an_unresolved_sal():
    """Sal = 1.5 grid spacings: the closed form's Sal and Str come out about 8 % and 13 %
    long (interpolated ACF); after calibrating on 8 seeds, fresh seeds hit them."""
    targets = {"Sq": 0.3, "Sal": 1.5, "Str": 0.3, "Std": -20.0}
    shape, noise = (256, 256), 0.3 ** 2 / 11
    with pytest.warns(UserWarning, match="grid spacings"):
        cal = P.calibrate(targets, shape, seeds=range(8), iterations=2, noise_variance=noise)
    assert len(cal.history) == 3 and cal.history[0][0] == T.as_targets(targets).as_dict()
    with pytest.warns(UserWarning, match="grid spacings"):
        assert cal.closed_form == T.hyperparameters_for(**targets, noise_variance=noise)
    assert cal.hyperparameters.lengthscales[1] < cal.closed_form.lengthscales[1]
    fresh = range(100, 108)
    before = T.summarize(T.achieved_parameters(cal.closed_form, shape, seeds=fresh))
    after = T.summarize(T.achieved_parameters(cal.hyperparameters, shape, seeds=fresh))
    for name in ("Sal", "Str"):
        (m0, s0), (m1, s1) = before[name], after[name]
        bias0, bias1 = m0 - targets[name], m1 - targets[name]
        assert bias0 > 4 * s0 / math.sqrt(8), (name, m0, s0)  # measurably long
        assert abs(bias1) <= 4 * s1 / math.sqrt(8) and abs(bias1) < abs(bias0) / 2, \
            (name, m1, s1)
    z, h = P.simulate_with_targets(targets, shape, seed=5, noise_variance=noise,
                                   calibration=cal)
    assert h == cal.hyperparameters and z.shape == shape
    with pytest.raises(ValueError, match="calibration was made for other shape"):
        P.simulate_with_targets(targets, (128, 128), seed=5, noise_variance=noise,
                                calibration=cal)
    with pytest.raises(ValueError, match="targets"):
        P.simulate_with_targets(dict(targets, Sq=0.31), shape, seed=5, noise_variance=noise,
                                calibration=cal)


def test_calibrate_errors():
    t = {"Sq": 1.0, "Sal": 8.0, "Str": 0.1, "Std": 0.0}
    with pytest.raises(ValueError, match="at least 2 seeds"):
        P.calibrate(t, (64, 64), seeds=[1])
    with pytest.raises(ValueError, match="iterations must be an integer >= 1"):
        P.calibrate(t, (64, 64), iterations=0)
    with pytest.raises(ValueError, match="correct must name"):
        P.calibrate(t, (64, 64), correct=("Sa",))
    # grooves 80 long on a 40-point field: Str does not exist on it
    with pytest.raises(ValueError, match="Str is undefined on .* use a larger shape"):
        P.calibrate(t, (40, 40), seeds=range(3), iterations=1, noise_variance=0.0)
    cal = P.calibrate(t, (40, 40), seeds=range(3), iterations=1, noise_variance=0.0,
                      correct=("Sq", "Sal"))
    assert cal.hyperparameters.lengthscales[1] / cal.hyperparameters.lengthscales[0] \
        == pytest.approx(0.1)  # Str left as prescribed
