"""The 2-D spectral mixture (roughgp.surface_models.spectral_mixture): its spectrum and ACVF agree,
the Whittle fit recovers a known mixture and finds a lay's period, the file is versioned and
hostile files are refused by name, draws are exact and seeded, and too narrow a peak is
refused with the reason."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
import scipy.optimize

from roughgp.surface_models import spectral_mixture
from roughgp.surface_models.fit import fit_sm_model
from roughgp.surface_models.model import FittedModel, ModelFileError
from roughgp.surface_models.spectral_mixture import Mixture2D, sm2d_acvf, sm2d_psd
from model_file_refusal import assert_refused

SPACING = (1.0, 1.0)
#: a broad roughness at zero frequency and a lay of period 12.5 um at 30 degrees
TRUTH = Mixture2D(weights=np.array([0.5, 1.0]),
                  means=np.array([[0.0, 0.0], [0.08 * math.cos(math.radians(30)),
                                               0.08 * math.sin(math.radians(30))]]),
                  bandwidths=np.array([[0.08, 0.04], [0.006, 0.012]]),
                  angles=np.radians([20.0, 30.0]), noise=0.01)


def _model(mixture=TRUTH, **fields):
    return FittedModel("sm2d", mixture.hyperparameters(), SPACING,
                       cutoffs={"form": "plane", "s_um": None, "l_um": None}, **fields)


def test_spectrum_and_acvf_are_one_covariance():
    """The ACVF at lag 0 is the summed weights; its DFT on a large grid is the aliased
    spectrum (um^4), and the spectrum sums to the variance plus the noise."""
    n = 256
    lag = (np.arange(n) - n // 2).astype(float)
    lags = np.stack(np.meshgrid(lag, lag, indexing="xy"), -1)   # (x, y) order
    acvf = sm2d_acvf(lags, TRUTH)
    assert acvf[n // 2, n // 2] == pytest.approx(1.5)
    latent = dataclass_replace(TRUTH, noise=1e-300)
    spectrum = np.real(np.fft.fft2(np.fft.ifftshift(acvf)))
    f = np.fft.fftfreq(n)
    fy, fx = np.meshgrid(f, f, indexing="ij")
    model = sm2d_psd(fy, fx, latent, SPACING)
    assert np.max(np.abs(spectrum - model)) < 1e-6 * model.max()
    assert sm2d_psd(fy, fx, TRUTH, SPACING).sum() / n ** 2 == pytest.approx(1.51, rel=1e-6)


def dataclass_replace(m, **changes):
    import dataclasses
    return dataclasses.replace(m, **changes)


def test_the_whittle_gradient_is_the_derivative():
    rng = np.random.default_rng(0)
    z = _model().simulate((48, 48), seed=1)
    spec = spectral_mixture._spectrum(z, SPACING)
    x = spectral_mixture._pack(TRUTH) + 0.05 * rng.standard_normal(13)
    value, grad = spectral_mixture._loss(x, spec, 2, 1.0)
    numeric = scipy.optimize.approx_fprime(x, lambda v: spectral_mixture._loss(v, spec, 2, 1.0)[0],
                                           1e-6)
    assert np.allclose(grad, numeric, rtol=1e-3, atol=1e-3 * np.abs(numeric).max())


@pytest.fixture(scope="module")
def drawn():
    """128 x 128 points drawn from TRUTH, and the fit."""
    z = _model().simulate((128, 128), seed=5)
    return z, fit_sm_model(z, SPACING)


def test_the_fit_recovers_a_known_mixture(drawn):
    z, fit = drawn
    hp = fit.model.hyperparameters
    assert fit.model.equation == "sm2d" and fit.model.stage == "form-removed"
    means = np.column_stack([hp["frequencies_x_per_um"], hp["frequencies_y_per_um"]])
    # the lay's peak found within one frequency bin (1/128 per um), up to the sign of +-mu
    lay = TRUTH.means[1]
    nearest = min(np.min(np.hypot(*(means - s * lay).T)) for s in (1, -1))
    assert nearest < 1 / 128
    # the variance conserved: the mixture plus the noise against the heights' variance
    total = sum(hp["weights_um2"]) + hp["noise_variance_um2"]
    assert total == pytest.approx(np.var(z), rel=0.05)
    assert [q for q, _, _ in fit.table][0] == 1 and len(fit.model.fit["bic"]) >= 2
    assert fit.model.fit["seconds"] > 0


def test_a_white_noise_field_is_one_broad_component_and_noise():
    z = np.random.default_rng(3).standard_normal((64, 64))
    fit = fit_sm_model(z, SPACING)
    hp = fit.model.hyperparameters
    # BIC does not add peaks to noise; the variance stays the noise's (within its error)
    assert len(hp["weights_um2"]) == 1, fit.table
    assert sum(hp["weights_um2"]) + hp["noise_variance_um2"] == pytest.approx(1.0, rel=0.1)


def test_draws_are_seeded_exact_and_of_the_model_variance():
    model = _model()
    a, b = model.simulate((64, 80), seed=7), model.simulate((64, 80), seed=7)
    assert np.array_equal(a, b) and a.shape == (64, 80)
    assert not np.array_equal(a, model.simulate((64, 80), seed=8))
    many = model.simulate((64, 64), seed=1, n_samples=8)
    assert np.var(many) == pytest.approx(1.51, rel=0.2)


def test_too_narrow_a_peak_is_refused_with_the_reason():
    narrow = dataclass_replace(TRUTH, bandwidths=np.array([[0.08, 0.04], [2e-4, 2e-4]]))
    with pytest.raises(ValueError, match="narrowest component .* torus of about"):
        _model(narrow).simulate((256, 256), seed=0)


def _record():
    return _model(marginal={"skewness": 0.2, "kurtosis": 3.5}).to_dict()


def test_the_file_round_trips(tmp_path):
    model = _model(marginal={"skewness": 0.2, "kurtosis": 3.5})
    path = model.save(tmp_path / "sm.json")
    again = FittedModel.load(path)
    assert again == model
    assert json.loads(path.read_text())["kind"] == "surface"
    assert "2-D spectral mixture: Q = 2" in again.describe()
    assert "peaks at periods 12.5 um" in again.describe()   # the lay; the roughness no peak
    lags = np.array([[3.0, -2.0], [0.0, 0.0]])
    assert np.allclose(again.kernel()(lags), sm2d_acvf(lags, TRUTH))
    assert again.latent_variance() == pytest.approx(1.5)


def _hp(name, value):
    return lambda r: r["hyperparameters"].__setitem__(name, value)


HOSTILE = [
    (_hp("weights_um2", [1.0] * 9), "weights_um2 must hold"),
    (_hp("weights_um2", []), "weights_um2 must be a non-empty list"),
    (_hp("weights_um2", [1.0, True]), "weights_um2[1] must be a number"),
    (_hp("weights_um2", [1.0, -1.0]), "weights_um2[1] must be a finite number"),
    (_hp("weights_um2", [1.0, 2.0, 3.0]), "must have the same length"),
    (_hp("weights_um2", [[1.0], [2.0]]), "weights_um2[0] must be a number"),
    (_hp("frequencies_x_per_um", [0.0, 0.7]), "frequencies_x_per_um[1] must be within the "
                                              "Nyquist"),
    (_hp("frequencies_y_per_um", [0.0, "0.1"]), "frequencies_y_per_um[1] must be a number"),
    (_hp("bandwidths_a_per_um", [0.08, 0.0]), "bandwidths_a_per_um[1] must be a finite"),
    (_hp("bandwidths_b_per_um", [0.08, 1e-9]), "bandwidths_b_per_um[1] must be within"),
    (_hp("bandwidths_b_per_um", [0.08, 5.0]), "bandwidths_b_per_um[1] must be within"),
    (_hp("axes_deg", [0.0, float("nan")]), "axes_deg[1] must be a finite number"),
    (_hp("axes_deg", [0.0, 1e4]), "axes_deg[1] must be a finite number"),
    (_hp("noise_variance_um2", -0.1), "noise_variance_um2 must be a finite"),
    (lambda r: r["hyperparameters"].pop("axes_deg"), "lacks axes_deg"),
    (lambda r: r["hyperparameters"].update(variance_um2=1.0), "unknown hyperparameters"),
    (_hp("weights_um2", {"a": 1.0}), "weights_um2 must be a non-empty list"),
    (lambda r: r.update(spacing_um=[1.0]), "spacing_um must hold 2 values"),
]


@pytest.mark.parametrize("spoil, words", HOSTILE, ids=[w[:40] for _, w in HOSTILE])
def test_hostile_files_are_refused_by_name(spoil, words):
    assert_refused(_record(), spoil, words)


def test_a_deeply_nested_file_is_refused(tmp_path):
    record = _record()
    record["hyperparameters"]["weights_um2"] = [[[[[[[[[1.0]]]]]]]]]
    path = tmp_path / "deep.json"
    path.write_text(json.dumps(record))
    with pytest.raises(ModelFileError, match="nested deeper"):
        FittedModel.load(path)


def test_bad_arguments():
    with pytest.raises(ValueError, match="marginal must be one of"):
        fit_sm_model(np.zeros((32, 32)), 1.0, marginal="weibull")
    with pytest.raises(ValueError, match="at least 16 x 16"):
        fit_sm_model(np.zeros((8, 40)), 1.0)
    with pytest.raises(ValueError, match="max_components must be an integer in"):
        fit_sm_model(np.random.default_rng(0).standard_normal((32, 32)), 1.0,
                     max_components=9)
    with pytest.raises(ValueError, match="constant"):
        fit_sm_model(np.ones((32, 32)), 1.0)


def test_a_lay_is_reproduced_by_the_mixture_and_not_by_eq18():
    """A sinusoidal lay (period 16 um at 11.5 degrees, amplitude 1.5 um) on an eq 18 roughness
    (variance 0.25 um^2), 128 x 128: with the measured heights (IAAFT, the lay's heights are
    not Gaussian) the spectral mixture leaves at most 2 of 13 parameters outside 19
    simulations, eq 18 more (measured on three seeds: eq 18 5, 3 and 5 outside; the mixture
    1, 1 and 0, Sal just outside), and the mixture has a component at the lay's frequency."""
    from roughgp.checking.model_check import check_model
    from roughgp.gp.kernels import RotatedExponentialKernel
    from roughgp.sampling import sample_grid
    from roughgp.surface_models.ladder import fit_rung
    n = 128
    rough = sample_grid(RotatedExponentialKernel(0.25, (8.0, 3.0), 0.3), (n, n), seed=1)[0]
    y, x = np.indices((n, n)).astype(float)
    lay = 1.5 * np.sin(2 * np.pi * (x * math.cos(0.2) + y * math.sin(0.2)) / 16.0 + 1)
    z = rough + lay + np.random.default_rng(11).normal(0, 0.05, (n, n))
    outside, models = {}, {}
    for name in ("eq18", "sm"):
        models[name], _ = fit_rung(name, z, 1.0, n_blocks=6, marginal="iaaft")
        outside[name] = check_model(models[name], z, 1.0, seed=0).outside
    assert len(outside["sm"]) <= 2 < len(outside["eq18"]), outside
    hp = models["sm"].hyperparameters
    means = np.column_stack([hp["frequencies_x_per_um"], hp["frequencies_y_per_um"]])
    lay_frequency = np.array([math.cos(0.2), math.sin(0.2)]) / 16.0
    assert min(np.min(np.hypot(*(means - s * lay_frequency).T)) for s in (1, -1)) < 1 / n


def test_draws_with_johnson_heights_search_the_embedding_once(monkeypatch):
    """The model's ACVF says which model it is (roughgp.surface_models.keyed_acvf), so a
    check's second draw reuses the first's embedding: mnt-2's half with this model and Johnson
    heights took about 2 minutes per draw, 19 to 99 draws per check; another model's
    hyperparameters are not served the cached one."""
    from roughgp.non_gaussian import draws
    from roughgp.sampling import grid_sampler
    monkeypatch.setattr(grid_sampler, "_EMBEDDINGS", {})
    monkeypatch.setattr(draws, "_INPUTS", {})
    searched = []
    embed = grid_sampler.circulant.embed
    monkeypatch.setattr(grid_sampler.circulant, "embed",
                        lambda *args, **kw: searched.append(1) or embed(*args, **kw))
    model = _model(marginal={"skewness": 0.8, "kurtosis": 4.5})
    first = model.simulate((48, 40), seed=3)
    once = len(searched)   # 1, or 2 where the exact embedding failed and a clipped one was made
    assert once >= 1
    assert np.array_equal(first, model.simulate((48, 40), seed=3)) and len(searched) == once
    assert not np.array_equal(first, model.simulate((48, 40), seed=4))
    assert len(searched) == once
    other = Mixture2D(TRUTH.weights * 2, TRUTH.means, TRUTH.bandwidths, TRUTH.angles,
                      TRUTH.noise)
    _model(other, marginal={"skewness": 0.8, "kurtosis": 4.5}).simulate((48, 40), seed=3)
    assert len(searched) > once
    assert model.kernel().cache_key() != _model(other).kernel().cache_key()


def test_a_tabulated_acvf_is_keyed_by_its_table_too():
    """The measured PSD's ACVF is read on the grid of the field it was fitted on: two models
    with the same PSD fitted on fields of other shapes are other ACVFs for the cache."""
    from roughgp.surface_models.keyed_acvf import model_key
    hp = {"psd_um4": [[1.0, 2.0], [3.0, 4.0]], "frequency_min_per_um": 0.01}
    assert model_key("measured-psd", hp, (1.0, 1.0, 64, 64)) != \
        model_key("measured-psd", hp, (1.0, 1.0, 64, 128))
    assert model_key("measured-psd", hp, (1.0, 1.0, 64, 64)) == \
        model_key("measured-psd", dict(reversed(list(hp.items()))), (1.0, 1.0, 64, 64))
    assert model_key("measured-psd", hp) != model_key("sm2d", hp)
