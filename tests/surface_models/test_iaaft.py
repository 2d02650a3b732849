"""The IAAFT marginal (roughgp.surface_models.iaaft): the distribution is the measured one, the
spectrum stays close, the same seed gives the same surface, hostile marginal fields refused."""

from __future__ import annotations

import dataclasses
import json
import math
from pathlib import Path

import numpy as np
import pytest
import scipy.fft
import scipy.ndimage
import scipy.stats

from roughgp.gp.kernels import RotatedExponentialKernel
from roughgp.sampling import sample_grid
from roughgp.surface_models import iaaft
from roughgp.surface_models.fit import fit_psd_model, fit_surface_model
from roughgp.surface_models.model import FittedModel
from model_file_refusal import assert_refused

DATA = Path(__file__).resolve().parents[2] / "data"

KERNEL = RotatedExponentialKernel(1.0, (8.0, 3.0), math.radians(30))


def _lognormal(seed, shape=(96, 96)):
    return np.exp(sample_grid(KERNEL, shape, seed=seed)[0])


def test_quantile_table_keeps_the_extremes_and_reproduces_the_sample():
    h = _lognormal(0)
    q, tail = iaaft.quantile_table(h)
    assert len(q) == iaaft.N_QUANTILES and tail == pytest.approx(0.5 / h.size)
    assert q[0] == h.min() and q[-1] == h.max() and np.all(np.diff(q) >= 0)
    values = iaaft.quantile_values(q, tail, h.size)
    np.testing.assert_allclose(np.quantile(values, [0.01, 0.5, 0.99]),
                               np.quantile(h, [0.01, 0.5, 0.99]), rtol=0.01)
    # more points than measured: beyond the extremes, continued (not clamped)
    more = iaaft.quantile_values(q, tail, 4 * h.size)
    assert more[-1] > h.max() and more[0] < h.min()


def test_iaaft_keeps_the_distribution_exactly_and_the_spectrum_closely():
    h = _lognormal(1)
    q, tail = iaaft.quantile_table(h)
    g = sample_grid(KERNEL, (128, 128), seed=5)[0]
    values = iaaft.quantile_values(q, tail, g.size)
    x, rounds = iaaft.iaaft(g, values, 20)
    np.testing.assert_array_equal(np.sort(x, axis=None), values)
    target = np.abs(scipy.fft.rfftn(g)) * np.sqrt(np.var(values) / np.var(g))
    target[0, 0] = 0.0

    def error(rounds_run):
        got = np.abs(scipy.fft.rfftn(iaaft.iaaft(g, values, rounds_run)[0]))
        got[0, 0] = 0.0
        return np.linalg.norm(got - target) / np.linalg.norm(target)

    # this heavy-tailed case (max 92 um, sd 4.2 um) converges slowly: 0.49, 0.24, 0.18
    assert error(20) < 0.3 and error(20) < 0.6 * error(1) and error(50) < error(20)
    assert rounds == 20


def test_a_model_with_the_iaaft_marginal_reproduces_the_heights():
    z = _lognormal(2)
    model = fit_psd_model(z, 1.0, marginal="iaaft").model
    assert model.marginal_method == "iaaft" and "IAAFT" in model.describe()
    sims = model.simulate((96, 96), seed=3, n_samples=6)
    skew = lambda a: float(np.mean((a - a.mean()) ** 3) / np.std(a) ** 3)  # noqa: E731
    measured = skew(z)
    simulated = [skew(s) for s in sims]
    gaussian = fit_psd_model(z, 1.0).model.simulate((96, 96), seed=3, n_samples=6)
    assert abs(np.median(simulated) - measured) < 0.25 * measured
    assert max(abs(skew(s)) for s in gaussian) < 0.5  # the Gaussian rung cannot
    # each simulation is a sample of the population: its extremes vary (no copy of the
    # measured ones; two crops may share a value of the population's discrete set)
    maxima = {float(s.max()) for s in sims}
    assert len(maxima) >= 3 and maxima != {float(z.max())}


def test_seeded_and_on_every_surface_equation(tmp_path):
    z = _lognormal(3, (64, 64))
    for model in (fit_psd_model(z, 1.0, marginal="iaaft").model,
                  fit_surface_model(z, 1.0, marginal="iaaft", n_blocks=4).model,
                  fit_surface_model(z, 1.0, marginal="iaaft", nu=1.5, n_blocks=4).model):
        again = FittedModel.load(model.save(tmp_path / "m.json"))
        a, b = model.simulate((40, 50), seed=9), again.simulate((40, 50), seed=9)
        np.testing.assert_array_equal(a, b)
        assert not np.array_equal(a, model.simulate((40, 50), seed=10))


def test_the_johnson_marginal_on_the_psd_model():
    z = _lognormal(4)
    model = fit_psd_model(z, 1.0, marginal="johnson").model
    assert model.marginal_method == "johnson"
    sims = model.simulate((96, 96), seed=0, n_samples=4)
    assert np.median([np.mean((s - s.mean()) ** 3) / np.std(s) ** 3 for s in sims]) > 1.0


def _record():
    model = fit_psd_model(_lognormal(5, (48, 48)), 1.0, marginal="iaaft").model
    return json.loads(json.dumps(model.to_dict()))


def _set_quantile(index, value):
    return lambda r: r["marginal"]["quantiles_um"].__setitem__(index, value)


HOSTILE = [
    (lambda r: r["marginal"].update(quantiles_um=[1.0, 2.0]), "list of 3 to 2001"),
    (lambda r: r["marginal"].update(quantiles_um="1 2 3"), "quantiles_um must be a list"),
    (_set_quantile(5, -1e6), "non-decreasing"),
    (_set_quantile(5, float("inf")), "quantiles_um[5] must be a finite number"),
    (_set_quantile(5, True), "quantiles_um[5] must be a number"),
    (lambda r: r["marginal"].update(quantiles_um=[1.0] * 10), "not all equal"),
    (lambda r: r["marginal"].update(iterations=0), "iterations must be an integer in [1, 1000]"),
    (lambda r: r["marginal"].update(iterations=2.5), "iterations must be an integer"),
    (lambda r: r["marginal"].update(tail_probability=0.5), "tail_probability"),
    (lambda r: r["marginal"].pop("tail_probability"), "lacks tail_probability"),
    (lambda r: r["marginal"].update(extra=1), "unknown extra"),
    (lambda r: r["marginal"].update(method="aaft"), "marginal must be null"),
]


@pytest.mark.parametrize("spoil, words", HOSTILE, ids=[w for _, w in HOSTILE])
def test_hostile_marginals_are_refused(spoil, words):
    assert_refused(_record(), spoil, words)


def test_with_an_l_filter_the_filtered_heights_distribution_is_matched():
    """Long smooth waves (variance 25 um^2) plus short spiky roughness (lognormal): after the
    L-filter the measured heights are heavy-tailed. The IAAFT marginal of the filtered heights,
    matched above the cut-off, gives the filtered simulations that kurtosis; the marginal of the
    form-removed heights (dominated by the long waves) does not."""
    from roughgp.surface_models.chain import form_removed, marginal_of, rest_of_chain
    long_waves = 5.0 * sample_grid(RotatedExponentialKernel(1.0, (40.0, 40.0), 0.0), (128, 128),
                                   seed=1)[0]
    spikes = np.exp(1.2 * sample_grid(RotatedExponentialKernel(1.0, (1.5, 1.5), 0.0),
                                      (128, 128), seed=2)[0])
    z = long_waves + spikes
    kurt = lambda a: float(np.mean((a - a.mean()) ** 4) / np.var(a) ** 2)  # noqa: E731
    banded = fit_psd_model(z, 1.0, l=20.0, marginal="iaaft")
    assert banded.model.marginal["above_l_um"] == 20.0
    measured = kurt(banded.texture.sl)
    assert measured > 8.0
    heights = form_removed(z, (1.0, 1.0), banded.model.cutoffs).sl
    whole = dataclasses.replace(banded.model, marginal=marginal_of(heights, "iaaft"))
    for model, close in ((banded.model, True), (whole, False)):
        sims = model.simulate((128, 128), seed=5, n_samples=4)
        filtered = [kurt(rest_of_chain(model, s, (1.0, 1.0)).sl) for s in sims]
        assert (abs(np.median(filtered) - measured) < 0.3 * measured) == close, filtered


def test_the_band_the_filter_passes_is_remapped_until_it_has_the_target_distribution():
    """One remap of the band above the cut-off leaves what the Gaussian filter passes of the
    sum nearer a Gaussian than the target (the filter is no sharp cut); the band rounds
    remap it again until the correction is small (iaaft.band_rounds)."""
    field = sample_grid(RotatedExponentialKernel(1.0, (30.0, 30.0), 0.0), (128, 128), seed=3)[0]
    values = np.sort(np.random.default_rng(4).lognormal(0.0, 0.8, field.size))
    values -= values.mean()  # the filtered heights' distribution: mean 0
    remap = lambda f: iaaft.iaaft(f, values)[0]  # noqa: E731
    sigma = iaaft._filter_sigma(20.0)

    def band_misfit(surface):
        band = surface - scipy.ndimage.gaussian_filter(surface, sigma, mode="reflect")
        return float(np.sqrt(np.mean((np.sort(band, axis=None) - values) ** 2) / np.var(values)))

    once = band_misfit(iaaft.iaaft_above(field, remap, 20.0, 1.0, rounds=1))
    rounds = band_misfit(iaaft.iaaft_above(field, remap, 20.0, 1.0))
    assert rounds < once / 3, (once, rounds)
    _, residuals = iaaft.band_rounds(iaaft.iaaft_above(field, remap, 20.0, 1.0, rounds=1),
                                     values, (sigma, sigma))
    assert residuals[0] > residuals[-1] and len(residuals) < iaaft.BAND_ROUNDS


def test_a_measured_map_s_filtered_heights_are_among_its_simulations():
    """data/matrix-3.txt (an AFM map; L 0.8 um): the measured-psd model with the IAAFT
    marginal, fitted on its left half and checked there, drew filtered heights nearer a
    Gaussian than the measured ones after one remap of the band (Sa, Sk and Sku outside)."""
    from roughgp.checking.model_check import check_model
    from roughgp.io.measurement import read_measurement
    m = read_measurement(DATA / "matrix-3.txt")
    left = m.z[:, :128]
    model = fit_psd_model(left, m.spacing, l=0.8, marginal="iaaft").model  # fit ground's L
    assert model.marginal["above_l_um"] == 0.8
    check = check_model(model, left, m.spacing, seed=2)
    assert not {"Sa", "Sk", "Sku"} & set(check.outside), check.outside


@pytest.mark.parametrize("l_um", [None, 20.0])
def test_remap_sd_is_the_sd_of_what_the_remap_acts_on(l_um):
    """iaaft.remap_sd: the model's sd (with an L-filter, of what the filter passes) against
    40 draws of 181 x 181 points."""
    draws = sample_grid(KERNEL, (181, 181), seed=4, n_samples=40)
    if l_um is not None:
        sigma = iaaft._filter_sigma(l_um)
        draws = np.stack([d - scipy.ndimage.gaussian_filter(d, sigma, mode="reflect")
                          for d in draws])
    expected = iaaft.remap_sd(KERNEL, 0.0, (181, 181), 1.0, l_um)
    assert abs(expected / np.sqrt(np.mean(draws ** 2)) - 1) < 0.03
    assert iaaft.remap_sd(KERNEL, 0.5, (181, 181), 1.0, l_um) > expected


def test_the_simulations_spread_as_a_correlated_surface_s_do():
    """The IAAFT sample is the draw's own scores through the quantile function: on a Gaussian
    surface the simulations' Sq, skewness and kurtosis spread about as the Gaussian model's
    simulations' do (their sds' ratios 0.94, 0.80 and 0.84). A sample drawn point by point
    spread them less (0.76, 0.59 and 0.47: only the crop from a field of twice the points
    gave it any spread)."""
    z = sample_grid(KERNEL, (128, 128), seed=5)[0]
    spread = {}
    for marginal in ("gaussian", "iaaft"):
        sims = fit_psd_model(z, 1.0, marginal=marginal).model.simulate((128, 128), seed=6,
                                                                        n_samples=24)
        flat = sims.reshape(len(sims), -1)
        spread[marginal] = np.array([np.std(np.log(flat.std(axis=1))),
                                     np.std(scipy.stats.skew(flat, axis=1)),
                                     np.std(scipy.stats.kurtosis(flat, axis=1))])
    ratios = spread["iaaft"] / spread["gaussian"]
    assert np.mean(ratios) > 0.75 and np.all(ratios < 1.3), ratios
