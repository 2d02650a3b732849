"""Tests of roughgp.metrology.periodicity."""

import numpy as np
import pytest

from roughgp.metrology import periodicity as per


def test_periodicity_of_a_sine_is_one_and_of_white_noise_is_zero():
    x = np.arange(4000) * 0.5
    sine = np.sin(2 * np.pi * x / 50.0)
    assert np.allclose(per.periodicity(sine, 50.0, spacing=0.5, n_periods=5), 1.0, atol=1e-2)
    noise = np.random.default_rng(1).standard_normal((20, 4000))
    assert np.all(np.abs(per.periodicity(noise, 50.0, spacing=0.5)) < 0.02)


def test_periodicity_follows_a_decaying_acvf():
    # an AR(1) with coefficient a has autocorrelation a^h
    rng = np.random.default_rng(2)
    a, n = 0.9, 200_000
    e = rng.standard_normal(n)
    z = np.empty(n)
    z[0] = e[0] / np.sqrt(1 - a * a)
    for i in range(1, n):
        z[i] = a * z[i - 1] + e[i]
    got = per.periodicity(z, 5.0, n_periods=3)
    assert np.allclose(got, a ** np.array([5, 10, 15]), atol=0.02)


def test_short_wavelength_share_splits_two_sines():
    x = np.arange(1024.0)
    z = np.sin(2 * np.pi * x / 128) + 0.5 * np.sin(2 * np.pi * x / 8)  # variance 0.5 + 0.125
    assert per.short_wavelength_share(z, 16.0) == pytest.approx(0.125 / 0.625, rel=1e-9)
    assert per.short_wavelength_share(np.tile(z, (3, 1)), 16.0) == pytest.approx(0.2, rel=1e-9)


@pytest.mark.parametrize("call, match", [
    (lambda: per.periodicity(np.ones(100), 5.0), "constant"),
    (lambda: per.periodicity(np.arange(100.0), 0.0), "period"),
    (lambda: per.periodicity(np.arange(100.0), 30.0, n_periods=4), "n_periods"),
    (lambda: per.periodicity(np.ones((2, 2, 2)), 1.0), "shape"),
    (lambda: per.short_wavelength_share(np.arange(100.0), 1.5), "cutoff_wavelength"),
    (lambda: per.short_wavelength_share([1.0, np.nan, 2.0, 3.0], 4.0), "finite"),
])
def test_errors(call, match):
    with pytest.raises(ValueError, match=match):
        call()
