"""Tests of roughgp.models.turned: the synthetic turned profiles and surfaces (section 3.3 stand-ins)."""

import math

import numpy as np
import pytest

from roughgp.metrology import levelling, texture
from roughgp.models import turned


def test_kinematic_rt_is_the_arc_sagitta_and_about_f2_over_8r():
    assert turned.kinematic_rt(250.0, 800.0) == pytest.approx(800 - math.sqrt(800 ** 2 - 125 ** 2))
    assert turned.kinematic_rt(100.0, 1200.0) == pytest.approx(100.0 ** 2 / (8 * 1200.0), rel=1e-3)
    with pytest.raises(ValueError, match="nose_radius"):
        turned.kinematic_rt(250.0, 100.0)


def test_ideal_profile_is_a_train_of_arcs_with_known_moments():
    feed, radius = 200.0, 1000.0
    x = np.arange(0.0, 40 * feed, 0.25)
    z = turned.kinematic_profile(x, feed, radius)
    # lowest points at the arc centres k * feed, cusps of height Rt half-way between
    assert z[np.searchsorted(x, 7 * feed)] == pytest.approx(0.0, abs=1e-12)
    assert z.max() == pytest.approx(turned.kinematic_rt(feed, radius), rel=1e-9)
    p = texture.profile_parameters(z, spacing=0.25)
    # wide dales, narrow hills: heights of a near-parabola, skewness ~ +0.64, kurtosis ~ 2.14
    assert p["Rsk"] == pytest.approx(0.639, abs=0.01)
    assert p["Rku"] == pytest.approx(2.143, abs=0.01)
    assert p["RSm"] == pytest.approx(feed, rel=1e-3)
    assert np.mean(z < z.mean()) == pytest.approx(1 / math.sqrt(3), abs=0.01)


def test_turned_profile_is_seeded_and_measurement_like():
    params = turned.RUBERT_LIKE
    x, z = turned.turned_profile(4096, spacing=1.0, seed=3)
    x2, z2 = turned.turned_profile(4096, spacing=1.0, seed=3)
    _, z3 = turned.turned_profile(4096, spacing=1.0, seed=4)
    assert np.array_equal(z, z2) and np.array_equal(x, x2) and not np.array_equal(z, z3)
    assert x[1] - x[0] == 1.0 and x.shape == z.shape == (4096,)
    p = texture.profile_parameters(z, spacing=1.0)
    assert p["RSm"] == pytest.approx(params.feed, rel=0.02)
    assert p["Rt"] == pytest.approx(params.rt, rel=0.3)  # deviations add to the kinematic Rt
    assert p["Rsk"] > 0.3  # still wide dales, narrow hills
    # the deviations are there: the profile differs from the ideal arcs by about their size
    x_ideal = turned.kinematic_profile(x, params.feed, params.nose_radius)
    assert np.std(np.diff(z)) > np.std(np.diff(x_ideal))


def test_tilt_is_added_and_levelling_removes_it():
    params = turned.TurnedParameters(tilt=0.01)
    x, z = turned.turned_profile(2048, params=params, seed=1)
    _, flat = turned.turned_profile(2048, seed=1)
    assert np.allclose(z - flat, 0.01 * x)
    levelled = levelling.level(z, spacing=1.0)
    assert abs(np.polyfit(x, levelled, 1)[0]) < 1e-12


def test_turned_surface_has_feed_marks_along_y():
    params = turned.RUBERT_LIKE
    z = turned.turned_surface((64, 1024), seed=2)
    assert z.shape == (64, 1024)
    assert np.array_equal(z, turned.turned_surface((64, 1024), seed=2))
    rows = texture.profile_parameters(z[10], spacing=1.0)
    assert rows["RSm"] == pytest.approx(params.feed, rel=0.03)
    # along a feed mark (a column) the height varies far less than across the marks
    assert np.mean(np.std(z, axis=0)) < 0.2 * np.mean(np.std(z, axis=1))


@pytest.mark.parametrize("kwargs, match", [
    (dict(feed=-1.0), "feed"),
    (dict(nose_radius=50.0), "nose_radius"),
    (dict(feed_jitter=100.0), "feed_jitter"),
    (dict(noise_sd=-0.1), "noise_sd"),
    (dict(edge_lengthscale=0.0), "edge_lengthscale"),
    (dict(noise_sd=float("nan")), "noise_sd"),
])
def test_parameter_errors_name_the_parameter(kwargs, match):
    with pytest.raises(ValueError, match=match):
        turned.TurnedParameters(**kwargs)


def test_call_errors():
    with pytest.raises(ValueError, match="n must be"):
        turned.turned_profile(8)
    with pytest.raises(ValueError, match="spacing"):
        turned.turned_profile(64, spacing=0.0)
    with pytest.raises(ValueError, match="shape"):
        turned.turned_surface((8, 64))
    with pytest.raises(ValueError, match="tilt"):
        turned.turned_profile(64, params=turned.TurnedParameters(tilt=(0.1, 0.2, 0.3)))
    with pytest.raises(ValueError, match="seed"):
        turned.turned_profile(64, seed=-1)
