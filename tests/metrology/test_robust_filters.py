"""Gaussian regression filters, plain and robust (ISO 16610-31 / -71), and the ISO 13565-1
filter for stratified surfaces, on the cases of their standards and literature: a sine at the
cut-off, a parabola up to the ends, a spike, a deep valley, a step, a plateau-honed profile.

No maintained package implements these filters (surfalize 0.19.2 and SurfaceTopography 1.27.1
have the plain Gaussian only): the independent check is a slow per-point weighted least-squares
fit (numpy's lstsq) written here.
"""

import math

import numpy as np
import pytest

from roughgp.experiments.spurious_points import plateau_honed_profile, stratified_comparison
from roughgp.metrology.filters import gaussian_filter
from roughgp.metrology.robust_filters import (
    GAMMA,
    WEIGHT_FLOOR,
    regression_filter,
    regression_transmission,
    robust_gaussian_filter,
    robust_l_filter,
    tukey_biweight,
)
from roughgp.metrology.stratified import stratified_l_filter, stratified_mean_line
from roughgp.metrology.texture_heights import material_ratio_parameters
from roughgp.metrology.texture_report import filtered_parameters

N, D, LC = 4000, 1.0, 400.0
X = np.arange(N) * D
INNER = slice(1000, 3000)


def _reference(z, cutoff, order, delta=None):
    """The regression mean line point by point with numpy's weighted lstsq (no FFT, no
    moments): the independent implementation."""
    gamma = GAMMA[order]
    measured = np.isfinite(z)
    delta = measured.astype(float) if delta is None else delta
    out = np.full(z.shape, np.nan)
    for k in np.flatnonzero(measured):
        u = (X[measured] - X[k]) / (gamma * cutoff)
        w = np.exp(-math.pi * u * u) * delta[measured]
        w[np.abs(u) > math.sqrt(-math.log(WEIGHT_FLOOR) / math.pi)] = 0.0  # the same window
        design = np.vander(u, order + 1, increasing=True)
        sw = np.sqrt(w)
        coef = np.linalg.lstsq(design * sw[:, None], z[measured] * sw, rcond=None)[0]
        out[k] = coef[0]
    return out


def test_gamma_of_the_second_order_filter_is_the_literature_value():
    assert GAMMA[2] == pytest.approx(0.7309, abs=5e-5)  # Seewig 2005, ISO 16610-31
    assert GAMMA[0] == pytest.approx(0.4697, abs=5e-5)  # ISO 16610-21


@pytest.mark.parametrize("order", [0, 2])
@pytest.mark.parametrize("wavelength", [LC, 0.5 * LC, 3 * LC])
def test_transmission_of_a_sine(order, wavelength):
    z = np.sin(2 * np.pi * X / wavelength)
    mean = regression_filter(z, D, LC, order=order, robust=False).mean
    amplitude = np.max(np.abs(mean[INNER]))
    expected = float(regression_transmission(wavelength, LC, order))
    assert amplitude == pytest.approx(expected, abs=2e-4)
    if wavelength == LC:
        assert amplitude == pytest.approx(0.5, abs=2e-4)


def test_order_zero_is_the_gaussian_filter_with_holes():
    z = np.random.default_rng(0).normal(size=N)
    z[100:130] = np.nan
    z[2000] = np.nan
    mean = regression_filter(z, D, LC, order=0, robust=False).mean
    plain = gaussian_filter(z, D, LC)
    assert np.array_equal(np.isnan(mean), np.isnan(z))
    assert np.nanmax(np.abs(mean - plain)) < 1e-6


@pytest.mark.parametrize("order", [0, 2])
def test_against_a_pointwise_weighted_least_squares(order):
    rng = np.random.default_rng(1)
    z = np.cumsum(rng.normal(size=N))[:N]
    z[500:520] = np.nan
    sub = slice(0, N, 37)
    mean = regression_filter(z, D, LC, order=order, robust=False).mean
    ref = _reference(z, LC, order)
    assert np.nanmax(np.abs(mean[sub] - ref[sub])) < 1e-6 * np.nanstd(z)


def test_robust_iteration_against_the_pointwise_reference():
    """The robust mean line is the pointwise fit with its own final weights (a fixed point)."""
    rng = np.random.default_rng(2)
    z = 0.1 * rng.normal(size=N)
    z[[700, 1800, 2600]] = [30.0, -25.0, 12.0]
    result = regression_filter(z, D, LC, order=2, robust=True, tol=1e-9, max_iter=200)
    assert result.converged
    ref = _reference(z, LC, 2, delta=result.weights)
    sub = slice(0, N, 53)
    assert np.max(np.abs(result.mean[sub] - ref[sub])) < 1e-6
    # the weights are the biweight of the residuals with c = 4.4 median |r|
    r = z - result.mean
    c = 4.4 * np.median(np.abs(r))
    assert result.c == pytest.approx(c, rel=1e-6)
    assert np.allclose(result.weights, tukey_biweight(r, c), atol=1e-6)


def test_second_order_reproduces_a_parabola_up_to_the_ends():
    q = 2e-5 * (X - 1300.0) ** 2 - 3e-3 * X
    second = regression_filter(q, D, LC, order=2, robust=False).mean
    assert np.max(np.abs(second - q)) < 1e-9 * np.max(np.abs(q))
    zeroth = gaussian_filter(q, D, LC)  # the zeroth-order end correction bends at the ends
    assert np.max(np.abs(zeroth - q)[:50]) > 1.0


def test_second_order_surface_reproduces_a_quadric():
    iy, ix = np.indices((80, 120)).astype(float)
    q = 1e-3 * (ix - 40) ** 2 + 5e-4 * (iy - 20) ** 2 + 2e-4 * ix * iy + 0.01 * ix
    q[30:33, 60:70] = np.nan
    mean = regression_filter(q, (1.0, 2.0), 40.0, order=2, robust=False).mean
    assert np.nanmax(np.abs(mean - q)) < 1e-8


def test_spike_and_deep_valley_are_not_followed():
    rng = np.random.default_rng(3)
    z = 0.1 * rng.normal(size=N)
    z[2000] = 50.0  # a spike
    z[1000:1010] = -20.0  # a deep narrow valley
    plain = gaussian_filter(z, D, LC)
    robust = robust_gaussian_filter(z, D, LC)
    assert abs(plain[2000]) > 0.2 and abs(plain[1005]) > 0.5  # the Gaussian follows them
    assert abs(robust[2000]) < 0.05 * abs(plain[2000])
    assert abs(robust[1005]) < 0.05 * abs(plain[1005])
    # far from the features (more than a cut-off) both mean lines agree within 0.1 noise sd
    far = np.r_[1600:1800, 2500:3500]
    assert np.max(np.abs(robust[far] - plain[far])) < 0.01 + 0.05 * 0.1 * 10


def test_far_from_features_robust_equals_gaussian():
    rng = np.random.default_rng(4)
    z = np.sin(2 * np.pi * X / 3000) + 0.3 * rng.normal(size=N)
    plain = gaussian_filter(z, D, LC)
    robust = regression_filter(z, D, LC, order=0).mean
    assert np.max(np.abs(robust[INNER] - plain[INNER])) < 0.1 * 0.3


def test_step_is_smoothed_by_both_filters():
    """A finding, not a virtue: on a step the robust filter, like the Gaussian, smooths the
    transition (its residuals are large on both sides); a cut-off away both reach the levels."""
    z = np.where(X < 2000, 0.0, 10.0) + 0.1 * np.random.default_rng(5).normal(size=N)
    plain = gaussian_filter(z, D, LC)
    robust = robust_gaussian_filter(z, D, LC)
    assert abs(robust[2025] - 10) > 2 and abs(plain[2025] - 10) > 2
    assert abs(robust[2000 + int(1.5 * LC)] - 10) < 0.05
    assert abs(robust[2000 - int(1.5 * LC)]) < 0.05


def test_plateau_honed_profile_stratified_and_robust_beat_gaussian():
    """The ISO 13565-1 literature case: the Gaussian mean line sinks into the valleys, so its
    roughness plateau sits above zero and Rk, Rpk come out too large; the two-pass filter
    reduces that, the robust filter removes most of it."""
    table = stratified_comparison()
    true = table["true roughness"]

    def error(name):
        p = table[name]
        return (abs(p["plateau"] - true["plateau"]), abs(p["Rk"] - true["Rk"]),
                abs(p["Rpk"] - true["Rpk"]))

    for i in range(3):
        assert error("ISO 13565-1")[i] < 0.6 * error("Gaussian")[i]
        assert error("robust")[i] < 0.2 * error("Gaussian")[i]


def test_stratified_mean_line_on_a_profile_without_valleys_is_close_to_gaussian():
    """Suppressing nothing but the lower half of a symmetric profile's fine roughness: the
    reference line rises by about the mean of the positive half-normal part (0.8 sigma / 2)."""
    rng = np.random.default_rng(6)
    z = 0.5 * rng.normal(size=N)
    line = stratified_mean_line(z, D, LC)
    assert np.median(line[INNER]) == pytest.approx(0.5 * 0.3989, abs=0.03)


def test_nan_stays_nan_and_holes_take_no_weight():
    z = 0.01 * X
    z[1000:1100] = np.nan
    for f in (lambda a: regression_filter(a, D, LC, order=2, robust=True).mean,
              lambda a: stratified_mean_line(a, D, LC)):
        mean = f(z)
        assert np.array_equal(np.isnan(mean), np.isnan(z))
    mean = regression_filter(z, D, LC, order=2, robust=True).mean
    assert np.nanmax(np.abs(mean - z)) < 1e-9  # a line through the hole, to the ends


def test_surface_spike_is_not_followed():
    rng = np.random.default_rng(7)
    clean = rng.normal(size=(120, 160))
    z = clean.copy()
    z[60, 80] = 200.0
    plain = gaussian_filter(z, 1.0, 40.0) - gaussian_filter(clean, 1.0, 40.0)
    def settled(a):  # both to their fixed point, so that the difference is the spike's
        return regression_filter(a, 1.0, 40.0, tol=1e-7, max_iter=200).mean

    robust = settled(z) - settled(clean)
    assert abs(plain[60, 80]) > 0.5  # the spike's pull on the Gaussian mean surface
    assert abs(robust[60, 80]) < 0.02 * abs(plain[60, 80])


def test_texture_with_robust_and_stratified_l_filters():
    truth, _, waviness = plateau_honed_profile(seed=2)
    z = (truth + waviness)[:4000]
    gauss = filtered_parameters(z, D, s=None, l=800.0)
    strat = filtered_parameters(z, D, s=None, l=800.0, l_kind="stratified")
    robust = filtered_parameters(z, D, s=None, l=800.0, l_kind="robust")
    assert "ISO 13565-1" in strat.operators[-1] and any("13565-1" in n for n in strat.notes)
    assert "robust" in robust.operators[-1]
    assert strat.parameters["Rpk"] < gauss.parameters["Rpk"]
    assert robust.parameters["Rk"] < gauss.parameters["Rk"]


@pytest.mark.parametrize("call, name", [
    (lambda: regression_filter(np.zeros(100), 1.0, 20.0, order=3), "order"),
    (lambda: regression_filter(np.zeros(100), 1.0, 1.0), "cutoff"),
    (lambda: regression_filter(np.zeros(100), 1.0, 20.0, tol=0), "tol"),
    (lambda: regression_filter(np.zeros(100), 1.0, 20.0, max_iter=0), "max_iter"),
    (lambda: regression_filter(np.full(100, np.nan), 1.0, 20.0), "measured"),
    (lambda: filtered_parameters(np.zeros((20, 20)), 1.0, l_kind="spline"), "l_kind"),
])
def test_bad_input_names_the_parameter(call, name):
    with pytest.raises(ValueError, match=name):
        call()


def test_flat_profile_is_its_own_mean_line():
    z = np.full(200, 3.0)
    result = regression_filter(z, 1.0, 20.0)
    assert result.converged and np.allclose(result.mean, 3.0)


@pytest.mark.parametrize("x", [-0.3678, -0.3, -0.5 / math.e, -0.1, -1e-3, -1e-12, -1e-300])
def test_the_lower_lambert_w_is_scipys(x):
    """GAMMA[2]'s W_{-1}, computed without scipy.special, against scipy.special.lambertw."""
    from scipy.special import lambertw

    from roughgp.metrology import robust_filters
    assert robust_filters._lambert_w_lower(x) == pytest.approx(lambertw(x, -1).real, rel=1e-14)


@pytest.mark.parametrize("x", [0.0, -0.5, 0.1, -1.0 / math.e])
def test_the_lower_lambert_w_refuses_outside_its_branch(x):
    from roughgp.metrology import robust_filters
    with pytest.raises(ValueError, match=r"x must be in \(-1/e, 0\)"):
        robust_filters._lambert_w_lower(x)
