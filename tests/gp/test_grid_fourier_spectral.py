"""Tests of roughgp.common.grid (layout conventions), roughgp.gp.fourier (eq 5 on a grid) and
roughgp.metrology.spectral (periodogram, Welch, empirical ACVF) -- Jawaid & Seewig, section 2.1-2.2.

Conventions under test (roughgp.common.grid): arrays are ``z[iy, ix]``, ``shape``/``spacing`` are in
array order ``(ny, nx)``/``(dy, dx)``, and points/lags/frequencies carry their components in
coordinate order ``(x, y)`` on a trailing axis.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy import special

from roughgp.common import grid
from roughgp.gp import fourier
from roughgp.metrology import spectral

PI = math.pi


# --------------------------------------------------------------------------- helpers

def _gauss_1d(lags, variance=1.0, ell=1.0):
    return variance * np.exp(-0.5 * (lags[..., 0] / ell) ** 2)


def _gauss_1d_psd(freqs, variance=1.0, ell=1.0):
    return variance * math.sqrt(2 * PI) * ell * np.exp(-2 * PI**2 * ell**2 * freqs[..., 0] ** 2)


def _direct_acvf(z, max_lag, unbiased):
    """O(n^2) reference: r[k] = sum_x z(x) z(x + k) / (N or number of pairs), array order."""
    z = np.atleast_2d(z) if z.ndim == 1 else z
    ny, nx = z.shape
    my, mx = max_lag
    out = np.zeros((2 * my + 1, 2 * mx + 1))
    for ky in range(-my, my + 1):
        for kx in range(-mx, mx + 1):
            total, count = 0.0, 0
            for iy in range(ny):
                for ix in range(nx):
                    jy, jx = iy + ky, ix + kx
                    if 0 <= jy < ny and 0 <= jx < nx:
                        total += z[iy, ix] * z[jy, jx]
                        count += 1
            out[ky + my, kx + mx] = total / (count if unbiased else z.size)
    return out


# --------------------------------------------------------------------------- grid.normalize

@pytest.mark.parametrize("shape", [(0,), (-3,), (4, 0), (2, 3, 4), (2.5,), (4, 2.0), "abc", (),
                                   ((2,),)])
def test_normalize_rejects_bad_shapes(shape):
    with pytest.raises(ValueError, match="shape"):
        grid.normalize(shape)


def test_normalize_rejects_3d_shape_explicitly():
    with pytest.raises(ValueError, match=r"\(n,\) or \(ny, nx\)"):
        grid.normalize((3, 3, 3), 1.0)


@pytest.mark.parametrize("spacing", [0.0, -1.0, (1.0, 0.0), (-0.5, 1.0), np.nan, np.inf,
                                     (1.0, np.nan)])
def test_normalize_rejects_non_positive_or_non_finite_spacing(spacing):
    with pytest.raises(ValueError, match="spacing"):
        grid.normalize((3, 4), spacing)


@pytest.mark.parametrize("spacing", [(1.0, 2.0, 3.0), np.ones((2, 2))])
def test_normalize_rejects_spacing_of_wrong_length(spacing):
    with pytest.raises(ValueError, match="spacing"):
        grid.normalize((3, 4), spacing)


def test_normalize_returns_int_tuple_and_broadcast_float_spacing():
    shape, spacing = grid.normalize(np.int64(5))
    assert shape == (5,) and type(shape[0]) is int
    np.testing.assert_array_equal(spacing, [1.0])
    assert spacing.dtype == np.float64

    shape, spacing = grid.normalize((np.int32(3), 4), 0.25)
    assert shape == (3, 4) and all(type(n) is int for n in shape)
    np.testing.assert_array_equal(spacing, [0.25, 0.25])

    shape, spacing = grid.normalize([3, 4], (2, 0.5))
    assert shape == (3, 4)
    np.testing.assert_array_equal(spacing, [2.0, 0.5])  # array order (dy, dx), kept


def test_normalize_does_not_alias_caller_spacing():
    given = np.array([1.0, 2.0])
    _, spacing = grid.normalize((2, 2), given)
    spacing[0] = 99.0
    assert given[0] == 1.0


# --------------------------------------------------------------------------- grid layout

def test_coordinates_2d_layout_with_different_spacings():
    dy, dx = 2.0, 0.5
    points = grid.coordinates((3, 4), (dy, dx))
    assert points.shape == (3, 4, 2)
    for iy in range(3):
        for ix in range(4):
            np.testing.assert_array_equal(points[iy, ix], (ix * dx, iy * dy))


def test_coordinates_1d_layout():
    points = grid.coordinates(5, 0.3)
    assert points.shape == (5, 1)
    np.testing.assert_allclose(points[:, 0], np.arange(5) * 0.3, rtol=0, atol=1e-15)


@pytest.mark.parametrize("shape", [(6, 7), (7, 6), (5, 5), (8, 4)])
def test_centred_lags_zero_at_half_and_components_xy(shape):
    dy, dx = 0.7, 1.3
    lags = grid.centred_lags(shape, (dy, dx))
    ny, nx = shape
    assert lags.shape == (ny, nx, 2)
    np.testing.assert_array_equal(lags[ny // 2, nx // 2], (0.0, 0.0))
    np.testing.assert_allclose(lags[0, :, 0], (np.arange(nx) - nx // 2) * dx)  # x along columns
    np.testing.assert_allclose(lags[:, 0, 1], (np.arange(ny) - ny // 2) * dy)  # y along rows
    assert np.all(lags[:, :, 0] == lags[:1, :, 0])  # x does not depend on iy
    assert np.all(lags[:, :, 1] == lags[:, :1, 1])  # y does not depend on ix


@pytest.mark.parametrize("n", [1, 2, 5, 6, 9, 10])
def test_centred_lags_1d(n):
    lags = grid.centred_lags(n, 0.5)
    assert lags.shape == (n, 1)
    assert lags[n // 2, 0] == 0.0
    np.testing.assert_allclose(lags[:, 0], (np.arange(n) - n // 2) * 0.5)


@pytest.mark.parametrize("shape", [(6, 7), (7, 6), (5, 8)])
def test_centred_frequencies_match_fftshift_fftfreq(shape):
    dy, dx = 0.7, 1.3
    freqs = grid.centred_frequencies(shape, (dy, dx))
    ny, nx = shape
    assert freqs.shape == (ny, nx, 2)
    np.testing.assert_array_equal(freqs[ny // 2, nx // 2], (0.0, 0.0))
    np.testing.assert_allclose(freqs[0, :, 0], np.fft.fftshift(np.fft.fftfreq(nx, dx)))
    np.testing.assert_allclose(freqs[:, 0, 1], np.fft.fftshift(np.fft.fftfreq(ny, dy)))
    assert np.all(freqs[:, :, 0] == freqs[:1, :, 0])
    assert np.all(freqs[:, :, 1] == freqs[:, :1, 1])


def test_fourier_grids_are_the_grid_module_grids():
    np.testing.assert_array_equal(fourier.lag_grid((4, 5), (1.0, 2.0)),
                                  grid.centred_lags((4, 5), (1.0, 2.0)))
    np.testing.assert_array_equal(fourier.frequency_grid((4, 5), (1.0, 2.0)),
                                  grid.centred_frequencies((4, 5), (1.0, 2.0)))


# --------------------------------------------------------------------------- fourier

def _random_even(shape, seed):
    """A random array on a centred odd-size grid with a[k] = a[-k]."""
    a = np.random.default_rng(seed).normal(size=shape)
    return 0.5 * (a + a[(slice(None, None, -1),) * len(shape)])


@pytest.mark.parametrize("shape, spacing", [((9,), 0.5), ((7, 11), (0.3, 1.7))])
def test_acvf_psd_transforms_are_inverses(shape, spacing):
    r = _random_even(shape, seed=3)
    s = fourier.acvf_to_psd(r, spacing)
    assert s.shape == shape and s.dtype == np.float64
    np.testing.assert_allclose(fourier.psd_to_acvf(s, spacing), r, rtol=0, atol=1e-12)
    s2 = _random_even(shape, seed=4)
    np.testing.assert_allclose(fourier.acvf_to_psd(fourier.psd_to_acvf(s2, spacing), spacing), s2,
                               rtol=0, atol=1e-12)


def test_acvf_to_psd_scaling_sum_rule():
    """S(0) = Delta^D sum r and r(0) = df^D sum S (the Riemann sums of eq 5)."""
    shape, spacing = (7, 9), (0.5, 2.0)
    r = _random_even(shape, seed=5)
    s = fourier.acvf_to_psd(r, spacing)
    assert s[3, 4] == pytest.approx(np.prod(spacing) * r.sum(), abs=1e-12)
    df = 1.0 / (np.asarray(shape) * np.asarray(spacing))
    assert r[3, 4] == pytest.approx(np.prod(df) * s.sum(), abs=1e-12)


@pytest.mark.parametrize("n, spacing, ell", [(61, 0.5, 2.0), (60, 0.5, 2.0), (101, 0.1, 0.7)])
def test_acvf_to_psd_gaussian_matches_closed_form_1d(n, spacing, ell):
    lags, freqs = fourier.lag_grid(n, spacing), fourier.frequency_grid(n, spacing)
    s = fourier.acvf_to_psd(_gauss_1d(lags, 2.0, ell), spacing)
    exact = _gauss_1d_psd(freqs, 2.0, ell)
    np.testing.assert_allclose(s, exact, rtol=0, atol=1e-8 * exact.max())
    r = fourier.psd_to_acvf(exact, spacing)
    np.testing.assert_allclose(r, _gauss_1d(lags, 2.0, ell), rtol=0, atol=1e-8)


def test_acvf_to_psd_anisotropic_gaussian_matches_closed_form_2d():
    """An anisotropic Gaussian (a along x, b along y) on a non-square grid with (dy, dx)
    different: a mix-up of the axes or of the component order would fail."""
    a, b, variance = 1.5, 0.6, 1.7
    shape, spacing = (45, 53), (0.2, 0.5)
    lags, freqs = fourier.lag_grid(shape, spacing), fourier.frequency_grid(shape, spacing)
    r = variance * np.exp(-0.5 * ((lags[..., 0] / a) ** 2 + (lags[..., 1] / b) ** 2))
    exact = variance * 2 * PI * a * b * np.exp(-2 * PI**2 * ((a * freqs[..., 0]) ** 2
                                                             + (b * freqs[..., 1]) ** 2))
    s = fourier.acvf_to_psd(r, spacing)
    np.testing.assert_allclose(s, exact, rtol=0, atol=1e-8 * exact.max())
    # the swapped model is clearly different, so the check above has power
    swapped = variance * 2 * PI * a * b * np.exp(-2 * PI**2 * ((b * freqs[..., 0]) ** 2
                                                               + (a * freqs[..., 1]) ** 2))
    assert np.abs(s - swapped).max() > 0.1 * exact.max()


def _rotated(lags, la=20.0, lb=3.0, angle=PI / 6):
    c, s = math.cos(angle), math.sin(angle)
    u = c * lags[..., 0] + s * lags[..., 1]
    v = -s * lags[..., 0] + c * lags[..., 1]
    return np.exp(-np.sqrt((u / la) ** 2 + (v / lb) ** 2))


def test_even_grid_with_function_not_vanishing_at_edge_raises():
    """On an even-size grid the most negative lag has no mirror: an even but rotated
    (not axis-symmetric) ACVF that is large there gives a complex transform -> ValueError."""
    with pytest.raises(ValueError, match="imaginary part"):
        fourier.acvf_to_psd(_rotated(fourier.lag_grid((8, 8))))
    with pytest.raises(ValueError, match="imaginary part"):
        fourier.psd_to_acvf(_rotated(fourier.frequency_grid((8, 8), 1.0), 0.2, 0.05))


def test_odd_grid_or_vanishing_function_is_accepted():
    s = fourier.acvf_to_psd(_rotated(fourier.lag_grid((9, 9))))  # odd: every lag has a mirror
    assert np.all(np.isfinite(s))
    lags = fourier.lag_grid((64, 64), 0.5)  # even, but r(edge) ~ exp(-16 / 0.5) ~ 0
    s = fourier.acvf_to_psd(_rotated(lags, 0.5, 0.3))
    assert np.all(np.isfinite(s))


def test_non_even_function_raises_on_odd_grid():
    lags = fourier.lag_grid(21, 0.5)
    with pytest.raises(ValueError, match="even"):
        fourier.acvf_to_psd(np.exp(-((lags[..., 0] - 1.0) ** 2)), 0.5)


def test_duality_errors_squared_exponential_well_resolved():
    errors = fourier.duality_errors(_gauss_1d, _gauss_1d_psd, (65,), 0.25)
    assert set(errors) == {"forward", "inverse", "lag0_deficit"}
    assert all(isinstance(v, float) for v in errors.values())
    # lags to +-8 ell (r ~ e^-32), Nyquist 2 / ell (S ~ e^-79): both errors are rounding
    assert errors["forward"] < 1e-10
    assert errors["inverse"] < 1e-10
    assert abs(errors["lag0_deficit"]) < 1e-10


def test_duality_errors_squared_exponential_2d_well_resolved():
    acvf = lambda t: np.exp(-0.5 * (t ** 2).sum(-1))  # noqa: E731
    psd = lambda f: 2 * PI * np.exp(-2 * PI**2 * (f ** 2).sum(-1))  # noqa: E731
    errors = fourier.duality_errors(acvf, psd, (33, 41), (0.4, 0.35))
    assert max(abs(v) for v in errors.values()) < 1e-8


def test_duality_errors_squared_exponential_aliasing_and_truncation():
    ell, spacing, n = 0.5, 1.0, 101
    acvf = lambda t: _gauss_1d(t, 1.0, ell)  # noqa: E731
    psd = lambda f: _gauss_1d_psd(f, 1.0, ell)  # noqa: E731
    errors = fourier.duality_errors(acvf, psd, (n,), spacing)
    # the PSD is a Gaussian of standard deviation 1 / (2 pi ell) in f: the share of the
    # variance beyond the Nyquist frequency 1 / (2 spacing) is erfc(f_N / (sd sqrt 2))
    sd = 1.0 / (2 * PI * ell)
    expected = special.erfc(0.5 / spacing / (sd * math.sqrt(2)))
    assert errors["lag0_deficit"] == pytest.approx(expected, rel=0.05)
    assert errors["lag0_deficit"] > 0.05
    assert errors["forward"] > 1e-2  # aliasing: sum_m S(f + m / Delta)
    # restricting to low frequencies reduces the aliasing error but does not remove it
    banded = fourier.duality_errors(acvf, psd, (n,), spacing, band=0.1)
    assert 0 < banded["forward"] < errors["forward"]
    assert banded["inverse"] == errors["inverse"]
    # truncation in lag: a grid covering only +-1.5 ell of a wide Gaussian
    wide = fourier.duality_errors(lambda t: _gauss_1d(t, 1.0, 4.0),
                                  lambda f: _gauss_1d_psd(f, 1.0, 4.0), (7,), 1.0)
    assert wide["forward"] > 0.1 and wide["inverse"] > 0.1


# --------------------------------------------------------------------------- periodogram

@pytest.mark.parametrize("shape, spacing", [((64,), 0.5), ((65,), 2.0), ((12, 17), (0.5, 3.0))])
def test_periodogram_parseval(shape, spacing):
    z = np.random.default_rng(7).normal(loc=0.3, size=shape)
    freqs, power = spectral.periodogram(z, spacing, demean=False)
    assert power.shape == shape
    assert freqs.shape == (*shape, len(shape))
    np.testing.assert_allclose(freqs, grid.centred_frequencies(shape, spacing))
    df = np.prod(1.0 / (np.asarray(shape) * np.broadcast_to(spacing, (len(shape),))))
    assert power.sum() * df == pytest.approx(np.mean(z**2), rel=1e-12)
    assert np.all(power >= 0)


def test_periodogram_demean_removes_zero_frequency_and_parseval_gives_variance():
    shape, spacing = (10, 13), (1.0, 0.5)
    z = np.random.default_rng(8).normal(loc=5.0, size=shape)
    freqs, power = spectral.periodogram(z, spacing)
    assert power[5, 6] == pytest.approx(0.0, abs=1e-20)
    np.testing.assert_array_equal(freqs[5, 6], (0.0, 0.0))
    df = 1.0 / (10 * 1.0 * 13 * 0.5)
    assert power.sum() * df == pytest.approx(np.var(z), rel=1e-12)


def test_periodogram_of_a_cosine_peaks_at_its_frequency_on_the_right_axis():
    ny, nx, dx, dy = 16, 32, 0.5, 1.0
    x = np.arange(nx) * dx
    z = np.tile(np.cos(2 * PI * 0.25 * x), (ny, 1))  # varies along x only, f_x = 0.25
    freqs, power = spectral.periodogram(z, (dy, dx))
    peak = np.unravel_index(np.argmax(power), power.shape)
    assert abs(freqs[peak][0]) == pytest.approx(0.25) and freqs[peak][1] == 0.0


# --------------------------------------------------------------------------- welch

def test_welch_integrates_to_the_variance_of_white_noise():
    sigma, spacing, n, seg = 2.0, 0.5, 2**16, 128
    z = np.random.default_rng(9).normal(scale=sigma, size=n)
    freqs, power = spectral.welch(z, spacing, segment_length=seg)
    assert freqs.shape == (seg, 1) and power.shape == (seg,)
    assert np.all(np.diff(freqs[:, 0]) > 0)
    np.testing.assert_allclose(freqs[:, 0], grid.centred_frequencies(seg, spacing)[:, 0])
    df = 1.0 / (seg * spacing)
    assert power.sum() * df == pytest.approx(sigma**2, rel=0.03)
    # flat: white noise of variance sigma^2 has S = sigma^2 * spacing at every frequency
    assert np.median(power) == pytest.approx(sigma**2 * spacing, rel=0.05)


@pytest.mark.parametrize("segment_length", [1, 0, 1001, 10.5, "64"])
def test_welch_segment_length_errors(segment_length):
    z = np.random.default_rng(0).normal(size=1000)
    with pytest.raises(ValueError, match="segment_length"):
        spectral.welch(z, segment_length=segment_length)


@pytest.mark.parametrize("overlap", [1.0, -0.1, 1.5, np.nan])
def test_welch_overlap_errors(overlap):
    z = np.random.default_rng(0).normal(size=1000)
    with pytest.raises(ValueError, match="overlap"):
        spectral.welch(z, segment_length=100, overlap=overlap)


def test_welch_rejects_surfaces():
    with pytest.raises(ValueError, match="profile"):
        spectral.welch(np.zeros((20, 20)), segment_length=10)


# --------------------------------------------------------------------------- empirical ACVF

def test_empirical_acvf_biased_lag0_is_mean_square():
    z = np.random.default_rng(10).normal(loc=1.0, size=(7, 9))
    lags, values = spectral.empirical_acvf(z, demean=False)
    assert values.shape == (13, 17) and lags.shape == (13, 17, 2)
    np.testing.assert_array_equal(lags[6, 8], (0.0, 0.0))
    assert values[6, 8] == pytest.approx(np.mean(z**2), rel=1e-12)
    _, demeaned = spectral.empirical_acvf(z)
    assert demeaned[6, 8] == pytest.approx(np.var(z), rel=1e-12)


@pytest.mark.parametrize("unbiased", [False, True])
@pytest.mark.parametrize("demean", [False, True])
def test_empirical_acvf_matches_direct_loop_1d(unbiased, demean):
    z = np.random.default_rng(11).normal(loc=0.5, size=11)
    lags, values = spectral.empirical_acvf(z, 0.5, unbiased=unbiased, demean=demean)
    ref = _direct_acvf(z - z.mean() if demean else z, (0, 10), unbiased)[0]
    assert values.shape == (21,)
    np.testing.assert_allclose(values, ref, rtol=0, atol=1e-12)
    np.testing.assert_allclose(lags[:, 0], (np.arange(21) - 10) * 0.5)


@pytest.mark.parametrize("unbiased", [False, True])
@pytest.mark.parametrize("max_lag", [None, 2, (3, 1)])
def test_empirical_acvf_matches_direct_loop_2d(unbiased, max_lag):
    ny, nx, spacing = 5, 6, (0.5, 2.0)
    z = np.random.default_rng(12).normal(size=(ny, nx))
    lags, values = spectral.empirical_acvf(z, spacing, max_lag=max_lag, unbiased=unbiased,
                                           demean=False)
    my, mx = (ny - 1, nx - 1) if max_lag is None else np.broadcast_to(max_lag, (2,))
    ref = _direct_acvf(z, (my, mx), unbiased)
    assert values.shape == (2 * my + 1, 2 * mx + 1)
    np.testing.assert_allclose(values, ref, rtol=0, atol=1e-12)
    assert lags.shape == (2 * my + 1, 2 * mx + 1, 2)
    for ky in (-my, 0, my):
        for kx in (-mx, 0, mx):
            np.testing.assert_allclose(lags[ky + my, kx + mx], (kx * spacing[1], ky * spacing[0]))


def test_empirical_acvf_components_order_constant_rows():
    """z[iy, ix] = f(iy): every row constant, so the unbiased ACVF does not depend on tau_x,
    which must be component 0 of the lags and vary along the last array axis."""
    ny, nx = 6, 9
    f = np.random.default_rng(13).normal(size=ny)
    z = np.repeat(f[:, None], nx, axis=1)
    lags, values = spectral.empirical_acvf(z, (1.0, 0.5), unbiased=True, demean=False)
    assert np.ptp(lags[..., 0], axis=0).max() == 0  # tau_x constant down a column
    assert np.ptp(lags[..., 0], axis=1).min() > 0  # ... and varies along a row
    for row in range(values.shape[0]):  # fixed tau_y, all tau_x
        np.testing.assert_allclose(values[row], values[row, nx - 1], rtol=1e-12, atol=1e-12)
    assert np.ptp(values[:, nx - 1]) > 1e-3  # along tau_y it does change
    # the biased estimate along tau_x is that value times (1 - |k_x| / n_x)
    _, biased = spectral.empirical_acvf(z, (1.0, 0.5), demean=False)
    kx = np.abs(np.arange(-(nx - 1), nx))
    np.testing.assert_allclose(biased[ny - 1], values[ny - 1, nx - 1] * (1 - kx / nx) * 1.0,
                               rtol=1e-12)


@pytest.mark.parametrize("max_lag", [-1, 6, (2, 9), (5, 0), (0, -1)])
def test_empirical_acvf_max_lag_errors(max_lag):
    z = np.zeros((5, 9)) + np.arange(9)
    with pytest.raises(ValueError, match="max_lag"):
        spectral.empirical_acvf(z, max_lag=max_lag)


def test_empirical_acvf_max_lag_with_wrong_number_of_axes_names_max_lag():
    with pytest.raises(ValueError, match="max_lag"):
        spectral.empirical_acvf(np.ones((5, 9)), max_lag=(1, 2, 3))


def test_empirical_acvf_max_lag_1d():
    z = np.random.default_rng(14).normal(size=20)
    _, values = spectral.empirical_acvf(z, max_lag=3)
    _, full = spectral.empirical_acvf(z)
    np.testing.assert_allclose(values, full[19 - 3:19 + 4], rtol=0, atol=1e-14)
    with pytest.raises(ValueError, match="max_lag"):
        spectral.empirical_acvf(z, max_lag=20)


# --------------------------------------------------------------------------- input checks

@pytest.mark.parametrize("func", [
    lambda z: spectral.periodogram(z),
    lambda z: spectral.welch(z, segment_length=4),
    lambda z: spectral.empirical_acvf(z),
], ids=["periodogram", "welch", "empirical_acvf"])
@pytest.mark.parametrize("bad", [np.nan, np.inf])
def test_non_finite_input_raises_naming_z(func, bad):
    z = np.arange(16.0)
    z[5] = bad
    with pytest.raises(ValueError, match=r"\bz\b"):
        func(z)


@pytest.mark.parametrize("z", [np.zeros((2, 2, 2)), np.zeros(1), np.float64(3.0), np.zeros((0,))])
def test_spectral_rejects_bad_dimensions(z):
    for func in (spectral.periodogram, spectral.empirical_acvf):
        with pytest.raises(ValueError, match="z must be"):
            func(z)


def test_near_direction_selects_the_lags_on_a_line():
    lags = grid.centred_lags((21, 31), (0.5, 0.25))
    mask, along = spectral.near_direction(lags, math.pi / 2, half_width=0.1)
    assert mask.sum() == 21 and np.all(lags[mask][:, 0] == 0)   # the y axis
    np.testing.assert_allclose(np.sort(along), np.arange(-10, 11) * 0.5)
    mask, along = spectral.near_direction(lags, math.pi / 4, half_width=1e-9)
    np.testing.assert_allclose(lags[mask][:, 0], lags[mask][:, 1])
    np.testing.assert_allclose(along, np.hypot(*lags[mask].T) * np.sign(lags[mask][:, 0]))
    with pytest.raises(ValueError, match="half_width"):
        spectral.near_direction(lags, 0.0, half_width=0.0)
    with pytest.raises(ValueError, match="lags"):
        spectral.near_direction(np.zeros((5, 3)), 0.0, half_width=1.0)
