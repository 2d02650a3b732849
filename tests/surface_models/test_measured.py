"""roughgp.surface_models: the model file, fits on measured heights, the model check, the fill
of a measured surface, and the moving-window kriging it uses (small seeded grids)."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from roughgp.checking.model_check import check_model
from roughgp.filling.global_fill import fill_gaps
from roughgp.filling.local_fill import fill_gaps_locally
from roughgp.filling.measured import fill_measured_surface
from roughgp.metrology.form import form_heights, remove_form
from roughgp.models import surfaces
from roughgp.surface_models.fit import fit_profile_model, fit_surface_model
from roughgp.surface_models.model import FittedModel, ModelFileError

EQ18 = {"variance_um2": 2.0, "lambda_a_um": 12.0, "lambda_b_um": 3.0, "angle_deg": 60.0,
        "noise_variance_um2": 0.05}


def _model(**changes):
    return FittedModel("eq18", {**EQ18, **changes}, (1.0, 1.0))


def _ground(shape=(96, 96), seed=3, angle=60.0):
    return surfaces.ground(shape, variance=2.0, lengthscales=(12.0, 3.0),
                           angle=math.radians(angle), noise_variance=0.05, seed=seed)


def test_model_file_round_trip_and_versions(tmp_path):
    model = FittedModel("eq18", EQ18, (2.0, 1.5), marginal={"skewness": -0.5, "kurtosis": 4.0},
                        operators=("F: plane",), data={"file": "x.x3p"})
    path = model.save(tmp_path / "m.json")
    again = FittedModel.load(path)
    assert again == model
    record = json.loads(path.read_text())
    assert record["format"] == "roughgp-model" and record["version"] == 2
    assert record["stage"] == model.stage
    old = {k: v for k, v in record.items() if k != "stage"}
    path.write_text(json.dumps({**old, "version": 1}))
    assert FittedModel.load(path).stage == "filtered"  # what version 1 fitted
    path.write_text(json.dumps({**record, "version": 3}))
    with pytest.raises(ModelFileError, match="version 3"):
        FittedModel.load(path)
    path.write_text("{not json")
    with pytest.raises(ModelFileError, match="not valid JSON"):
        FittedModel.load(path)
    path.write_text(json.dumps({"format": "something else"}))
    with pytest.raises(ModelFileError, match="not a roughgp model file"):
        FittedModel.load(path)


@pytest.mark.parametrize("changes, message", [
    ({"lambda_a_um": -1.0}, r"lambda_a_um must be a finite number in \(0"),
    ({"noise_variance_um2": float("nan")}, "noise_variance_um2 must be a finite number"),
    ({"angle_deg": float("inf")}, "angle_deg must be a finite number"),
])
def test_model_refuses_bad_hyperparameters(changes, message):
    with pytest.raises(ModelFileError, match=message):
        _model(**changes)


def test_model_refuses_an_incomplete_equation_and_bad_shapes():
    with pytest.raises(ModelFileError, match="lacks lambda_b_um"):
        FittedModel("eq18", {k: v for k, v in EQ18.items() if k != "lambda_b_um"}, (1.0, 1.0))
    with pytest.raises(ModelFileError, match="equation must be one of"):
        FittedModel("eq99", EQ18, (1.0, 1.0))
    with pytest.raises(ValueError, match=r"shape must be \(ny, nx\)"):
        _model().simulate((16,), seed=0)
    with pytest.raises(ValueError, match="exceeds"):
        _model().simulate((4096, 4096), seed=0, n_samples=2)


def test_simulate_is_seeded_and_has_the_model_variance():
    model = _model()
    a, b = model.simulate((64, 64), seed=5), model.simulate((64, 64), seed=5)
    np.testing.assert_array_equal(a, b)
    assert not np.array_equal(a, model.simulate((64, 64), seed=6))
    many = model.simulate((48, 48), seed=1, n_samples=12)
    assert many.shape == (12, 48, 48)
    # the pointwise variance over draws: sigma_k^2 + sigma^2 = 2.05, within Monte Carlo error
    assert abs(np.mean(many.var(axis=0, ddof=0)) - 2.05) < 0.25


def test_non_gaussian_model_reproduces_its_skewness():
    model = _model(noise_variance_um2=0.0)
    model = FittedModel("eq18", model.hyperparameters, (1.0, 1.0),
                        marginal={"skewness": -1.0, "kurtosis": 5.0})
    z = model.simulate((128, 128), seed=2, n_samples=4)
    h = z - z.mean(axis=(1, 2), keepdims=True)
    skew = np.mean(h ** 3, axis=(1, 2)) / np.mean(h ** 2, axis=(1, 2)) ** 1.5
    assert np.all(skew < -0.6)


def test_fit_surface_model_finds_the_lay_through_holes():
    z = _ground(angle=60.0)
    z[40:50, 30:45] = np.nan
    fit = fit_surface_model(z, 1.0, block=16, n_blocks=10, seed=0)
    hp = fit.model.hyperparameters
    angle = (hp["angle_deg"] - 60.0 + 90.0) % 180.0 - 90.0
    assert abs(angle) < 15.0
    assert hp["lambda_a_um"] > 1.5 * hp["lambda_b_um"]
    assert fit.model.data["missing_fraction"] > 0 and fit.model.operators == ("F: plane",)


def test_fit_profile_model_writes_an_eq21_model():
    x = np.arange(1024.0)
    rng = np.random.default_rng(0)
    z = np.sin(2 * np.pi * x / 64.0) + 0.1 * rng.standard_normal(x.size)
    model = fit_profile_model(z, 1.0, num_mixtures=2, seed=0, n_candidates=4).model
    hp = model.hyperparameters
    peak = int(np.argmax(np.asarray(hp["weights_um2"])))
    assert abs(1 / hp["frequencies_per_um"][peak] - 64.0) < 2.0
    draw = model.simulate(512, seed=1)
    assert draw.shape == (512,) and np.all(np.isfinite(draw))
    with pytest.raises(ValueError, match="missing"):
        fit_profile_model(np.r_[z[:100], np.nan], 1.0)


def test_check_model_places_its_own_draw_inside_and_flags_skewed_heights():
    model = _model()
    own = model.simulate((64, 64), seed=11)
    check = check_model(model, own, n_simulations=19, seed=0)
    outside = set(check.outside)
    assert len(outside) <= 4  # 13 parameters, each outside with p = 0.1 (they correlate)
    skewed = np.exp(own / 1.5)  # heavy upper tail: Ssk > 0, Sku > 3
    check = check_model(model, skewed, n_simulations=19, seed=0)
    assert {"Ssk", "Sku"} <= set(check.outside)
    assert {p.name for p in check.parameters} >= {"Sq", "Sal", "Str", "Std", "Spk", "Svk"}


def test_check_model_with_holes_gives_the_simulations_the_same_holes():
    model = _model()
    z = model.simulate((64, 64), seed=12)
    z[10:14, 20:30] = np.nan
    check = check_model(model, z, n_simulations=5, seed=0)
    assert check.notes and "unmeasured" in check.notes[0]
    assert all(math.isfinite(p.measured) for p in check.parameters)
    np.testing.assert_array_equal(np.isnan(check.simulated_heights), np.isnan(z))


def test_form_heights_give_back_the_removed_form():
    z = _ground((40, 60), seed=1)
    iy, ix = np.indices(z.shape)
    curved = z + 800.0 - np.sqrt(800.0 ** 2 - (ix - 30.0) ** 2)  # a cylinder along y
    curved[5:9, 10:20] = np.nan
    for form in ("plane", "polynomial", "cylinder"):
        residual, fit = remove_form(curved, 1.0, form)
        back = form_heights(fit, curved.shape, 1.0)
        measured = np.isfinite(curved)
        np.testing.assert_allclose((residual + back)[measured], curved[measured], atol=1e-9)


def test_local_and_global_fill_agree_on_a_well_conditioned_surface():
    z = _ground((64, 64), seed=4)
    truth = z.copy()
    z[20:26, 30:40] = np.nan
    z[50, 5:12] = np.nan
    kernel = surfaces.GrooveParameters(2.0, (12.0, 3.0), math.radians(60.0)).kernel()
    local = fill_gaps_locally(z, kernel, noise_variance=0.05, tile=16, margin=12)
    whole = fill_gaps(z, kernel, noise_variance=0.05, n_samples=0)
    missing = np.isnan(z)
    assert np.max(np.abs(local.mean[missing] - whole.mean[missing])) < 0.05
    error = local.mean[missing] - truth[missing]
    inside = np.abs(error) <= 2 * np.sqrt(local.sd[missing] ** 2 + 0.05)
    assert inside.mean() > 0.8 and np.all(local.sd[~missing] == 0)
    assert np.sqrt(np.mean(error ** 2)) < np.std(truth)


def test_fill_measured_surface_adds_the_cylinder_back():
    z = _ground((48, 64), seed=6)
    iy, ix = np.indices(z.shape)
    curved = z + 2000.0 - np.sqrt(2000.0 ** 2 - (ix - 32.0) ** 2)
    holed = curved.copy()
    holed[20:24, 40:48] = np.nan
    result = fill_measured_surface(holed, form="cylinder", seed=0, block=12, n_blocks=8)
    missing = np.isnan(holed)
    assert result.method == "local" and np.all(np.isfinite(result.filled))
    np.testing.assert_array_equal(result.filled[~missing], holed[~missing])
    assert np.sqrt(np.mean((result.filled - curved)[missing] ** 2)) < np.std(z)
    with pytest.raises(ValueError, match="method must be"):
        fill_measured_surface(holed, method="cubic")


def test_matern_variant_fits_a_smooth_surface_better_than_eq18():
    from roughgp.gp.acvf import rotated_exponential, rotated_matern
    from roughgp.inference.block_fit import fit_ground_to_valid_points
    from roughgp.sampling import sample_grid
    lags = np.array([[0.0, 0.0], [1.0, 2.0], [-3.0, 0.5]])
    np.testing.assert_allclose(rotated_matern(lags, 2.0, np.array([4.0, 1.0]), 0.3, 0.5),
                               rotated_exponential(lags, 2.0, np.array([4.0, 1.0]), 0.3))
    smooth = sample_grid(lambda t: rotated_matern(t, 1.0, np.array([10.0, 4.0]), 0.5, 2.5),
                         (72, 72), seed=2)[0]
    fits = {nu: fit_ground_to_valid_points(smooth, block=16, n_blocks=6, seed=0, nu=nu)
            for nu in (0.5, 2.5)}
    assert fits[2.5].log_likelihood > fits[0.5].log_likelihood + 50
    model = fit_surface_model(smooth, 1.0, block=16, n_blocks=6, seed=0, nu=2.5).model
    assert model.equation == "eq18-matern" and model.hyperparameters["nu"] == 2.5
    assert model.simulate((32, 32), seed=1).shape == (32, 32)
    with pytest.raises(ValueError, match="nu must be"):
        fit_ground_to_valid_points(smooth, nu=1.0)
