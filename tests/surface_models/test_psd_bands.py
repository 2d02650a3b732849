"""The measured-psd model on a surface whose long waves hold most of its variance: the table
scaled band by band (psd_table.scale_to_band), the IAAFT remap's scale read from the PSD
(measured_psd.passed_sd), and the filtered simulations' variance that both give."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import scipy.fft

from roughgp.gp.kernels import RotatedExponentialKernel
from roughgp.sampling import sample_grid
from roughgp.surface_models import psd_table
from roughgp.surface_models.chain import rest_of_chain
from roughgp.surface_models.fit import fit_psd_model, fit_surface_model
from roughgp.surface_models.measured_psd import passed_sd

ROOT = Path(__file__).resolve().parents[2]
SHAPE = (128, 128)
L_UM = 16.0


def _wavy(seed):
    """Fine roughness (eq 18, 3 um, variance 1) under long waves (eq 18, 300 um, variance 400:
    the filtered band holds under 1 % of the variance, as on many real maps)."""
    fine = sample_grid(RotatedExponentialKernel(1.0, (3.0, 2.0), 0.3), SHAPE, spacing=(1.0, 1.0),
                       seed=seed)[0]
    long = sample_grid(RotatedExponentialKernel(400.0, (300.0, 300.0), 0.0), SHAPE,
                       spacing=(1.0, 1.0), seed=seed + 50)[0]
    return fine + long


def _band(table, f_min, f_max, shape, s_um, l_um):
    qy, qx = scipy.fft.fftfreq(shape[0]), scipy.fft.fftfreq(shape[1])
    c = psd_table.psd_at(table, f_min, f_max, qy, qx) / (shape[0] * shape[1])
    h = psd_table.band_transmission(np.hypot(qy[:, None], qx[None, :]), s_um, l_um)
    return float(c.sum()), float((c * h).sum())


def test_the_table_holds_the_total_and_the_band_s_variance():
    h = _wavy(0)
    table, f_min, f_max = psd_table.estimate(h - h.mean(), (1.0, 1.0))
    total, band = _band(table, f_min, f_max, SHAPE, 2.5, L_UM)
    scaled = psd_table.scale_to_band(table, f_min, f_max, (1.0, 1.0), SHAPE, 1.3 * total,
                                     0.7 * band, s_um=2.5, l_um=L_UM)
    assert _band(scaled, f_min, f_max, SHAPE, 2.5, L_UM) == pytest.approx(
        (1.3 * total, 0.7 * band), rel=1e-3)
    # no positive pair of factors holds a band above the total: the band's variance alone
    alone = psd_table.scale_to_band(table, f_min, f_max, (1.0, 1.0), SHAPE, 0.5 * band, band,
                                    l_um=L_UM)
    assert _band(alone, f_min, f_max, SHAPE, None, L_UM)[1] == pytest.approx(band, rel=1e-3)


def test_the_band_transmission_is_iso_16610_s():
    """Half the amplitude at each cut-off (ISO 16610-61's Gaussian weighting), nothing of the
    mean through the L-filter."""
    assert psd_table.band_transmission([0.0], l_um=L_UM)[0] == 0.0
    assert psd_table.band_transmission([1 / L_UM], l_um=L_UM)[0] == pytest.approx(0.25)
    assert psd_table.band_transmission([1 / 2.5], s_um=2.5)[0] == pytest.approx(0.25)
    both = psd_table.band_transmission([0.1], s_um=2.5, l_um=L_UM)[0]
    assert both == pytest.approx(psd_table.band_transmission([0.1], s_um=2.5)[0]
                                 * psd_table.band_transmission([0.1], l_um=L_UM)[0])


@pytest.mark.parametrize("marginal", ["gaussian", "iaaft"])
def test_filtered_simulations_have_the_measured_band_s_variance(marginal):
    """The left half (256 x 128) of data/mnt-2-crop.x3p, L 0.8 um: the filtered band holds 0.3 %
    of the form-removed variance. Scaled to the total alone, the Gaussian draws' filtered
    variance was 2.3 times the measured; band-scaled, with the IAAFT remap scaled by the ACVF's
    clipped spectrum (iaaft.remap_sd), 0.51 times."""
    import roughgp
    measurement = roughgp.read(ROOT / "data" / "mnt-2-crop.x3p")
    z = measurement.z[:, :128]
    fit = fit_psd_model(z, measurement.spacing, marginal=marginal, l=0.8)
    measured = float(np.nanvar(fit.texture.sl))
    draws = fit.model.simulate(z.shape, seed=3, n_samples=4)
    filtered = [np.nanvar(rest_of_chain(fit.model, d, measurement.spacing).sl) for d in draws]
    assert np.mean(filtered) / measured == pytest.approx(1.0, abs=0.1)


def test_eq18_with_iaaft_heights_draws_the_measured_band_s_variance():
    """Eq 18 with IAAFT heights on the same half: its remap divides by iaaft.remap_sd, which
    leaks long waves into the band and depends on the field's shape (0.00119 um on the fitted
    256 x 128, 0.00116 on the population of twice the points the remap acts on). Keyed at the
    Hazen positions the draws' filtered variance was 0.81 times the measured; with the order
    scores over the fitted shape's sd, 1.06; over the population's, as the remap divides,
    1.00 (surface_models.order_scores)."""
    import roughgp
    measurement = roughgp.read(ROOT / "data" / "mnt-2-crop.x3p")
    z = measurement.z[:, :128]
    fit = fit_surface_model(z, measurement.spacing, marginal="iaaft", l=0.8)
    measured = float(np.nanvar(fit.texture.sl))
    draws = fit.model.simulate(z.shape, seed=3, n_samples=6)
    filtered = [np.nanvar(rest_of_chain(fit.model, d, measurement.spacing).sl) for d in draws]
    assert np.mean(filtered) / measured == pytest.approx(1.0, abs=0.04)


def test_the_remap_s_scale_is_the_sd_the_filter_passes_of_the_draws():
    fit = fit_psd_model(_wavy(2), 1.0, marginal="gaussian", l=L_UM)
    import scipy.ndimage
    from roughgp.surface_models.iaaft import _filter_sigma
    draws = fit.model.simulate((181, 181), seed=4, n_samples=8)
    sigma = _filter_sigma(L_UM)
    passed = [np.std(d - scipy.ndimage.gaussian_filter(d, sigma, mode="reflect")) for d in draws]
    assert passed_sd(fit.model, (181, 181), (1.0, 1.0), L_UM) == pytest.approx(
        np.sqrt(np.mean(np.square(passed))), rel=0.08)


@pytest.mark.parametrize("length", [2.0, 8.0])
def test_the_table_reads_back_a_smooth_spectrum_around_its_knee(length):
    """An eq 18-like isotropic spectrum, (1 + (2 pi length q)^2)^(-3/2), given exactly on a
    128 x 128 grid: the stored table read back holds each of 8 logarithmic bands' power within
    4 % above the lowest (the plain bin averages lost 12 % around the knee of length 8)."""
    qy = qx = scipy.fft.fftfreq(128)
    r = np.hypot(qy[:, None], qx[None, :])
    c = (1 + (2 * np.pi * length * r) ** 2) ** -1.5
    table, f_min, f_max = psd_table.log_polar_table(qy, qx, c)
    back = psd_table.psd_at(table, f_min, f_max, qy, qx)
    edges = f_min * np.exp(np.linspace(0, np.log(f_max / f_min) * 1.0001, 9))
    ratios = [back[(r >= a) & (r < b)].sum() / c[(r >= a) & (r < b)].sum()
              for a, b in zip(edges[:-1], edges[1:])]
    assert np.allclose(ratios[1:], 1.0, atol=0.04), np.round(ratios, 3)
