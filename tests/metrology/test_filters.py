"""ISO Gaussian filters (ISO 16610-21, -61), F-operators, default cut-offs, the S-F-L chain.

surfalize (GPL) is a test-only oracle here; roughgp never imports it.
"""

import warnings

import numpy as np
import pytest

from roughgp.metrology.filters import (
    PREFERRED_NESTING_INDICES,
    default_cutoffs,
    gaussian_filter,
    gaussian_kernel,
    l_filter,
    s_filter,
    surface_texture,
    transmission,
)
from roughgp.metrology.form import remove_cylinder, remove_form, remove_plane, remove_polynomial

surfalize = pytest.importorskip("surfalize")


def _amplitude(m, inner, coord=None, wavelength=None):
    """The amplitude of a sine of ``wavelength`` along ``coord`` in ``m[inner]`` (least
    squares on sin and cos: exact for any number of periods), or sqrt(2) * rms."""
    if wavelength is None:
        return float(np.sqrt(2 * np.nanmean(m[inner] ** 2)))
    phase = 2 * np.pi * coord[inner].ravel() / wavelength
    design = np.column_stack([np.sin(phase), np.cos(phase), np.ones_like(phase)])
    coef = np.linalg.lstsq(design, m[inner].ravel(), rcond=None)[0]
    return float(np.hypot(coef[0], coef[1]))


def _surf(z, dy, dx):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # surfalize warns on dx != dy
        return surfalize.Surface(z, dx, dy)


# --------------------------------------------------------------------------- transmission

@pytest.mark.parametrize("ratio, expected", [(1.0, 0.5), (10.0, 0.99309), (0.2, 0.0)])
def test_profile_transmission(ratio, expected):
    dx, cutoff = 0.5, 80.0
    x = np.arange(3000) * dx
    z = 3.0 * np.sin(2 * np.pi * x / (ratio * cutoff) + 0.3)
    mean_line = gaussian_filter(z, dx, cutoff)
    inner = slice(int(cutoff / dx), -int(cutoff / dx))
    amp = _amplitude(mean_line, inner, x, ratio * cutoff) / 3.0
    assert amp == pytest.approx(expected, abs=0.005)
    assert amp == pytest.approx(float(transmission(ratio * cutoff, cutoff)), abs=1e-3)
    if ratio == 1.0:  # 50 % within 1 %, and the L-filter keeps the other half
        assert abs(amp - 0.5) < 0.005
        rough = l_filter(z, dx, cutoff)
        assert _amplitude(rough, inner, x, cutoff) / 3.0 == pytest.approx(0.5, abs=0.005)


def test_areal_transmission_along_x_and_y_on_a_non_square_grid():
    ny, nx, dy, dx, cutoff = 90, 160, 2.0, 1.0, 25.0
    y, x = np.meshgrid(np.arange(ny) * dy, np.arange(nx) * dx, indexing="ij")
    inner = (slice(13, -13), slice(25, -25))
    for coord, lam, name in ((x, cutoff, "x"), (y, cutoff, "y"), (x, 8 * cutoff, "x long"),
                             (y, 4 * cutoff, "y long"), (y, cutoff / 4, "y short")):
        wave = np.sin(2 * np.pi * coord / lam)
        amp = _amplitude(gaussian_filter(wave, (dy, dx), cutoff), inner, coord, lam)
        assert amp == pytest.approx(float(transmission(lam, cutoff)), abs=0.005), name
        if lam == cutoff:
            assert abs(amp - 0.5) < 0.005, name


# --------------------------------------------------------------------------- NaN

def test_nan_stays_nan_and_a_hole_does_not_bias_its_neighbours():
    rng = np.random.default_rng(3)
    ny, nx, d, cutoff = 120, 140, 1.0, 16.0
    y, x = np.meshgrid(np.arange(ny) * d, np.arange(nx) * d, indexing="ij")
    # a long-wavelength surface (passes the filter) plus noise
    full = 2.0 * np.sin(2 * np.pi * x / 300) + np.cos(2 * np.pi * y / 250) \
        + 0.05 * rng.normal(size=x.shape)
    holed = full.copy()
    holed[50:70, 60:75] = np.nan
    a, b = gaussian_filter(full, d, cutoff), gaussian_filter(holed, d, cutoff)
    assert np.array_equal(np.isnan(b), np.isnan(holed))
    far = np.ones_like(full, bool)
    far[50 - 16:70 + 16, 60 - 16:75 + 16] = False
    assert np.nanmax(np.abs(a - b)[far]) < 1e-10  # outside the kernel: identical
    near = np.isfinite(b) & ~far  # beside the hole: nearly unbiased
    zero_filled = gaussian_filter(np.nan_to_num(holed), d, cutoff)  # no normalisation
    naive = np.abs(a - zero_filled)[near]
    ours = np.abs(a - b)[near]
    assert np.mean(ours) < 0.01 and np.max(ours) < 0.1
    assert np.mean(ours) < 0.05 * np.mean(naive)
    assert np.isnan(s_filter(holed, d, cutoff)[55, 65])


# --------------------------------------------------------------------------- surfalize

def test_gaussian_agrees_with_surfalize_on_the_interior_of_a_non_square_grid():
    rng = np.random.default_rng(0)
    ny, nx, dy, dx, cutoff = 150, 200, 1.5, 1.0, 25.0  # different shape and spacing
    z = rng.normal(size=(ny, nx))
    low = _surf(z, dy, dx).filter("lowpass", cutoff).data
    high = _surf(z, dy, dx).filter("highpass", cutoff).data
    border = (int(cutoff / dy) + 1, int(cutoff / dx) + 1)
    inner = (slice(border[0], -border[0]), slice(border[1], -border[1]))
    ours = gaussian_filter(z, (dy, dx), cutoff)
    scale = float(np.std(low[inner]))
    # surfalize truncates its kernel at 4 sigma (0.75 cut-offs), ours at 1 cut-off:
    # the dropped tail weight is ~6e-5, so agreement to 1e-3 of the filtered rms
    assert np.max(np.abs(ours - low)[inner]) < 1e-3 * scale
    assert np.max(np.abs(l_filter(z, (dy, dx), cutoff) - high)[inner]) < 1e-3 * scale
    # orientation: the spacings swapped give a clearly different answer
    swapped = gaussian_filter(z, (dx, dy), cutoff)
    assert np.max(np.abs(swapped - low)[inner]) > 0.2 * scale
    # a profile too
    p = z[0]
    low_p = _surf(p[None, :], 1.0, dx).filter("lowpass", cutoff).data[0]
    b = int(cutoff / dx) + 1  # one row: surfalize's reflect mode leaves y alone
    assert np.max(np.abs(gaussian_filter(p, dx, cutoff) - low_p)[b:-b]) < 1e-3 * np.std(low_p)


def test_plane_and_polynomial_agree_with_surfalize():
    rng = np.random.default_rng(1)
    ny, nx, dy, dx = 60, 90, 2.0, 0.5
    y, x = np.meshgrid(np.arange(ny) * dy, np.arange(nx) * dx, indexing="ij")
    z = 0.02 * x - 0.01 * y + 1e-3 * x * y + 2e-4 * (x - 20) ** 3 / 10 \
        + 0.1 * rng.normal(size=x.shape)
    z[10:20, 30:40] = np.nan
    plane, fit = remove_plane(z, (dy, dx))
    ref = _surf(z, dy, dx).level().data
    assert np.array_equal(np.isnan(plane), np.isnan(z))
    assert np.nanmax(np.abs(plane - ref)) < 1e-9
    assert fit.method == "plane" and fit.rms == pytest.approx(np.sqrt(np.nanmean(ref ** 2)))
    for degree in (2, 3):
        poly, fit = remove_polynomial(z, (dy, dx), degree)
        ref = _surf(z, dy, dx).detrend_polynomial(degree).data
        assert np.nanmax(np.abs(poly - ref)) < 1e-9
        assert fit.parameters["degree"] == degree
    # the reported coefficients rebuild the removed form
    poly, fit = remove_polynomial(z, (dy, dx), 2)
    p = fit.parameters
    u, v = x - p["xc"], y - p["yc"]
    form = sum(p[f"c[{i},{j}]"] * u ** i * v ** j for i in range(3) for j in range(3)
               if i + j <= 2)
    assert np.nanmax(np.abs(z - form - poly)) < 1e-9


# --------------------------------------------------------------------------- cylinder

@pytest.mark.parametrize("axis", ["y", "x"])
def test_cylinder_recovers_radius_and_axis(axis):
    rng = np.random.default_rng(7)
    ny, nx, dy, dx = 80, 110, 4.0, 2.0
    y, x = np.meshgrid(np.arange(ny) * dy, np.arange(nx) * dx, indexing="ij")
    radius, centre, tilt = 1200.0, 95.0, 0.02
    across, along = (x, y) if axis == "y" else (y, x)
    z = np.sqrt(radius ** 2 - (across - centre) ** 2) - radius + tilt * along \
        + 0.1 * rng.normal(size=x.shape)
    z[20:35, 40:60] = np.nan
    z[rng.random(z.shape) < 0.05] = np.nan
    residual, fit = remove_cylinder(z, (dy, dx), "auto")
    assert fit.method == "cylinder"
    assert fit.parameters["axis"] == (1.0 if axis == "y" else 0.0)
    assert fit.parameters["radius"] == pytest.approx(radius, rel=0.02)
    key = "axis_x0" if axis == "y" else "axis_y0"
    assert fit.parameters[key] == pytest.approx(centre, abs=2.0)
    assert fit.parameters["tilt"] == pytest.approx(tilt, abs=1e-3)
    assert fit.rms == pytest.approx(0.1, rel=0.1)
    assert np.array_equal(np.isnan(residual), np.isnan(z))
    # the plane leaves the curvature in, the polynomial of degree 2 nearly matches
    assert remove_plane(z, (dy, dx))[1].rms > 5 * fit.rms


def test_circle_of_a_profile():
    dx, radius = 1.0, 800.0
    x = np.arange(300) * dx
    z = -(np.sqrt(radius ** 2 - (x - 140.0) ** 2) - radius)  # concave
    residual, fit = remove_cylinder(z, dx)
    assert fit.parameters["radius"] == pytest.approx(radius, rel=1e-6)
    assert fit.parameters["convex"] == 0.0
    assert np.max(np.abs(residual)) < 1e-6


# --------------------------------------------------------------------------- defaults, chain

def test_default_cutoffs_profile_and_surface():
    dx = 0.5
    x = np.arange(8000) * dx
    c = default_cutoffs(1.0 * np.sin(2 * np.pi * x / 100.0), dx)  # Ra = 0.64 um
    assert (c.s, c.l) == (2.5, 800.0) and "ISO 4288" in c.reason
    c = default_cutoffs(0.05 * np.sin(2 * np.pi * x / 100.0), dx)  # Ra = 0.032 um
    assert c.l == 250.0
    c = default_cutoffs(1.0 * np.sin(2 * np.pi * x / 100.0), dx, by="RSm")  # RSm 100 um
    assert c.l == 250.0
    c = default_cutoffs(np.zeros((400, 1000)), (0.5, 1.0))  # 200 um x 1 mm
    assert c.l == 25.0 and c.l in PREFERRED_NESTING_INDICES
    assert c.s == 8.0 and c.s >= 3 * 1.0


def test_surface_texture_chain():
    rng = np.random.default_rng(5)
    ny, nx, d = 200, 260, 1.0
    y, x = np.meshgrid(np.arange(ny) * d, np.arange(nx) * d, indexing="ij")
    rough = np.sin(2 * np.pi * x / 10.0)  # passes S = 2.5, removed by nothing
    wavy = 3.0 * np.sin(2 * np.pi * y / 400.0)  # long: waviness
    z = 5 + 0.01 * x + 0.02 * y + rough + wavy + 0.01 * rng.normal(size=x.shape)
    z[5:15, 5:15] = np.nan
    t = surface_texture(z, d, form="plane", s=2.5, l=80.0)
    assert t.operators == ["F: plane", "S: Gaussian 2.5 um", "L: Gaussian 80 um"]
    inner = (slice(80, -80), slice(80, -80))
    amp = _amplitude(t.sl, inner, x, 10.0)
    # S = 2.5 spacings: the sampled kernel's transmission (sum of w_k cos(2 pi k d / 10))
    # is 0.967, the continuous one 0.958; the L-filter keeps all of a 10 um wave
    k = gaussian_kernel(2.5, d)
    sampled = float(np.sum(k * np.cos(2 * np.pi * (np.arange(k.size) - k.size // 2) * d / 10)))
    assert amp == pytest.approx(sampled * (1 - float(transmission(10.0, 80.0))), abs=0.003)
    assert abs(sampled - float(transmission(10.0, 2.5))) < 0.015
    assert np.allclose(t.sf, t.waviness + t.sl, equal_nan=True)
    assert np.isnan(t.sl[10, 10]) and np.isnan(t.primary[10, 10])
    t2 = surface_texture(z, d, form=None, s=None, l=None)
    assert t2.operators == ["F: none"] and np.allclose(t2.sl, z, equal_nan=True)
    t3 = surface_texture(z, d)  # defaults
    assert t3.cutoffs.l in PREFERRED_NESTING_INDICES and "preferred" in t3.cutoffs.reason


def test_fast_enough_for_a_large_surface():
    import time
    z = np.random.default_rng(0).normal(size=(1000, 1000))
    z[100:200, 300:400] = np.nan
    start = time.perf_counter()
    gaussian_filter(z, 1.0, 800.0)
    assert time.perf_counter() - start < 5.0  # about a second on one core


# --------------------------------------------------------------------------- bad input

@pytest.mark.parametrize("call, name", [
    (lambda: gaussian_filter(np.zeros(100), 1.0, -5.0), "cutoff"),
    (lambda: gaussian_filter(np.zeros(100), 1.0, 1.5), "cutoff"),
    (lambda: gaussian_filter(np.full(100, np.nan), 1.0, 10.0), "z"),
    (lambda: gaussian_filter(np.zeros(100), -1.0, 10.0), "spacing"),
    (lambda: gaussian_filter(np.zeros(100), 1.0, 10.0, edge="wrap"), "edge"),
    (lambda: s_filter(np.zeros((10, 10)), (1.0, 3.0), 5.0), "cutoff"),
    (lambda: surface_texture(np.zeros(100), 1.0, s=0.0, l=None), "s"),
    (lambda: surface_texture(np.zeros(100), 1.0, s=20.0, l=10.0), "s"),
    (lambda: remove_form(np.zeros(100), 1.0, "sphere"), "form"),
    (lambda: remove_polynomial(np.zeros(100), 1.0, -1), "degree"),
    (lambda: remove_cylinder(np.full((5, 5), np.nan), 1.0), "z"),
    (lambda: remove_cylinder(np.zeros((5, 5)), 1.0, "z"), "axis"),
    (lambda: remove_cylinder(np.zeros((5, 5)), 1.0), "curvature"),
    (lambda: remove_plane(np.full((5, 5), np.nan)), "z"),
])
def test_bad_input_names_the_parameter(call, name):
    with pytest.raises(ValueError, match=name):
        call()


def test_drop_edge():
    z = np.random.default_rng(2).normal(size=200)
    m = gaussian_filter(z, 1.0, 20.0, edge="drop")
    assert np.all(np.isnan(m[:20])) and np.all(np.isnan(m[-20:]))
    assert np.allclose(m[20:-20], gaussian_filter(z, 1.0, 20.0)[20:-20])


def test_a_given_l_is_not_explained_by_the_default_it_replaced():
    """`texture --l-filter 250` used to print the note of the default L (80 um) it replaced."""
    z = np.random.default_rng(0).normal(size=(96, 128))
    t = surface_texture(z, 2.0, s="auto", l=100.0)
    assert t.cutoffs.l == 100.0
    assert "L set by the caller" in t.cutoffs.reason and "largest preferred" not in t.cutoffs.reason
    assert "smallest preferred" in t.cutoffs.reason            # the automatic S is explained
    both = surface_texture(z, 2.0, s="auto", l="auto")
    assert "largest preferred" in both.cutoffs.reason and "caller" not in both.cutoffs.reason
