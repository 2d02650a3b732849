"""The eq18-field rung (roughgp.surface_models.field_model, issue 40 items 3 to 5): fitted
fields that follow a known gradient, a stationary map that comes back stationary, the model
file's schema, its draws, and the commands."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from roughgp.experiments.field_recovery import true_field
from roughgp.models.nonstationary import ParameterField, sample_nonstationary
from roughgp.surface_models.field_draw import field_at
from roughgp.surface_models.field_model import fit_field_model
from roughgp.surface_models.model import FittedModel, ModelFileError


def _run(capsys, *argv):
    from roughgp.cli.main import main
    code = main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return code, out, err


def _map(kind, seed, shape=(128, 256)):
    values = true_field(kind, shape)
    return sample_nonstationary(shape, 1.0, ParameterField(**values), n_kernels=8,
                                seed=seed)[0]


@pytest.fixture(scope="module")
def gradient_fit():
    return fit_field_model(_map("gradient", 0), 1.0, tiles=(2, 4), n_draws=20, seed=0)


def test_the_variance_field_follows_a_gradient(gradient_fit):
    """Variance 1 to 3 um^2 left to right: the trend's test rejects a constant, the fitted
    field rises along x (as a plane or, on four columns of noisy tiles, as a step: on this map
    the left column's tiles lie low and a step between it and the others fits better), and
    the truth lies within 2 reported standard errors at the anchors."""
    pooled = gradient_fit.pooled_of("log variance")
    assert pooled.p_trend < 0.01 and (pooled.slope[0] > 0 or pooled.step[:1] == ("x",))
    variance = np.asarray(gradient_fit.model.hyperparameters["variance_um2"])
    assert np.all(np.diff(variance, axis=1) >= 0)
    assert np.all(variance[:, -1] > 1.5 * variance[:, 0])
    truth = np.log(3.0 ** (gradient_fit.tiles.centres_x / 255))
    assert np.mean(np.abs(pooled.shrunk - truth[None, :]) <= 2 * pooled.shrunk_sd) >= 0.75
    lengths = np.asarray(gradient_fit.model.hyperparameters["lambda_a_um"])
    assert np.all(np.abs(np.log(lengths / 8.0)) < math.log(1.5))


def test_a_stationary_map_comes_back_stationary():
    fitted = fit_field_model(_map("stationary", 1), 1.0, tiles=(2, 4), n_draws=20, seed=0)
    hp = fitted.model.hyperparameters
    for name in ("variance_um2", "lambda_a_um", "lambda_b_um", "angle_deg"):
        values = np.asarray(hp[name])
        assert np.ptp(values) <= 0.1 * np.abs(values).mean() + 1.0, (name, values)
    assert fitted.pooled_of("log variance").slope == (0.0, 0.0)


def test_the_model_file_round_trip_and_its_draws(gradient_fit, tmp_path):
    model = gradient_fit.model
    path = model.save(tmp_path / "field.json")
    again = FittedModel.load(path)
    assert again.hyperparameters == json.loads(path.read_text())["hyperparameters"]
    a = again.simulate((64, 128), seed=3)
    b = again.simulate((64, 128), seed=3)
    assert a.shape == (64, 128) and np.array_equal(a, b)
    # the draws' local variance follows the field: the right columns rougher than the left
    draws = again.simulate((128, 256), seed=4, n_samples=8)
    left, right = draws[:, :, :64].var(), draws[:, :, -64:].var()
    assert 1.5 < right / left < 5.0
    values = field_at(again, (128, 256))
    assert values["variance"][:, -1].mean() > values["variance"][:, 0].mean()
    assert "parameter fields on 2 x 4 anchors" in again.describe()


def _record(model, **changes):
    record = model.to_dict()
    record["hyperparameters"].update(changes)
    return record


@pytest.mark.parametrize("changes, words", [
    (dict(variance_um2=[[1.0, 2.0]]), "variance_um2 must be a list of 2 rows"),
    (dict(lambda_a_um=[[1.0, 2.0, 3.0, float("nan")], [1.0] * 4]), "lambda_a_um[0][3]"),
    (dict(anchors_x_um=[1.0, 1.0, 2.0, 3.0]), "anchors_x_um must be strictly increasing"),
    (dict(angle_deg=[[1.0] * 4, [1.0, 2.0, 3.0, "4"]]), "angle_deg[1][3] must be a number"),
    (dict(anchors_y_um=list(range(40))), "anchors_y_um must hold"),
    (dict(steps=[1.0]), "steps must be an object"),
    (dict(steps={"noise": {"axis": "x", "at_um": 100.0}}), "steps has an unknown field"),
    (dict(steps={"variance_um2": {"axis": "z", "at_um": 100.0}}), "steps.variance_um2 must be"),
    (dict(steps={"variance_um2": {"axis": "x", "at_um": 1e6}}),
     "steps.variance_um2.at_um must lie strictly between"),
    (dict(steps={"variance_um2": {"axis": "x", "at_um": float("nan")}}),
     "steps.variance_um2.at_um must be a finite number"),
])
def test_the_schema_refuses_a_bad_field(gradient_fit, changes, words):
    with pytest.raises(ModelFileError) as error:
        FittedModel.from_dict(_record(gradient_fit.model, **changes))
    assert words in str(error.value)


def test_two_zones_are_fitted_and_drawn_as_two_zones():
    """Variance 1 and 3 um^2 on the two halves: the fit keeps a step of the variance at the
    boundary between the middle tiles (not a gradient), the model file holds it, the field
    jumps there, and the draws' variance is about 3 times larger right of it than left."""
    fitted = fit_field_model(_map("zones", 5), 1.0, tiles=(2, 4), n_draws=20, seed=0)
    pooled = fitted.pooled_of("log variance")
    assert pooled.step == ("x", float(np.mean(fitted.tiles.centres_x[1:3])))
    assert pooled.slope == (0.0, 0.0) and pooled.p_step < 0.01
    again = FittedModel.from_dict(json.loads(json.dumps(fitted.model.to_dict())))
    assert again.hyperparameters["steps"] == {"variance_um2": {"axis": "x",
                                                               "at_um": pooled.step[1]}}
    variance = field_at(again, (128, 256))["variance"]
    assert np.ptp(variance[:, :128]) < 1e-9 and np.ptp(variance[:, 128:]) < 1e-9
    assert 2.0 < variance[0, -1] / variance[0, 0] < 4.5
    draws = again.simulate((128, 256), seed=6, n_samples=8)
    assert 2.0 < draws[:, :, 128:].var() / draws[:, :, :128].var() < 4.5
    assert "variance steps at x = " in again.describe()


def test_the_schema_refuses_a_marginal(gradient_fit):
    record = gradient_fit.model.to_dict()
    record["marginal"] = {"skewness": 0.1, "kurtosis": 3.2}
    with pytest.raises(ModelFileError, match="eq18-field model draws Gaussian heights"):
        FittedModel.from_dict(record)


def test_it_has_no_single_kernel(gradient_fit):
    with pytest.raises(ValueError, match="no single kernel"):
        gradient_fit.model.kernel()


def test_the_commands_fit_check_and_refuse(capsys, tmp_path, gradient_fit):
    z = _map("gradient", 2, shape=(96, 128))
    np.save(tmp_path / "map.npy", z)
    code, text, err = _run(capsys, "fit", "ground", tmp_path / "map.npy", "--model", "field",
                           "--anchors", 2, 2, "--l-filter", "none", "--out",
                           tmp_path / "f.json")
    assert code == 0, err
    assert "log variance" in text and "p gradient" in text and "se anchor" in text
    anchor_sd = json.loads((tmp_path / "f.json").read_text())["fit"]["anchor_sd"]
    assert np.shape(anchor_sd["log variance"]) == (2, 2)
    assert np.all(np.asarray(anchor_sd["log variance"]) > 0)
    code, text, err = _run(capsys, "check", tmp_path / "f.json", tmp_path / "map.npy",
                           "--tiles", 2, 2, "--simulations", 5)
    assert code == 0, err
    assert "Sq" in text
    code, _, err = _run(capsys, "simulate", "--from", tmp_path / "f.json", "--shape", 32, 48,
                        "--out", tmp_path / "sim.npy")
    assert code == 0, err
    assert np.load(tmp_path / "sim.npy").shape == (32, 48)
    gradient_fit.model.save(tmp_path / "g.json")
    holes = z.copy()
    holes[40:44, 40:44] = np.nan
    np.save(tmp_path / "holes.npy", holes)
    code, _, err = _run(capsys, "fill", tmp_path / "holes.npy", "--model", tmp_path / "g.json",
                        "--out", tmp_path / "filled.npy")
    assert code == 2 and "no single kernel" in err, err


@pytest.mark.parametrize("extra, words", [
    (("--anchors", 2, 2), "--anchors applies to --model field and population only"),
    (("--model", "field", "--anchors", 0, 2), "--anchors must be two integers in [1, 32]"),
    (("--model", "field", "--marginal", "iaaft"), "--model field draws Gaussian heights"),
    (("--model", "field", "--anchors", 9, 2), "tiles must be (m, n)"),
])
def test_fit_field_refuses_what_does_not_apply(capsys, tmp_path, extra, words):
    np.save(tmp_path / "map.npy", np.random.default_rng(0).standard_normal((64, 64)))
    code, _, err = _run(capsys, "fit", "ground", tmp_path / "map.npy", *extra, "--l-filter",
                        "none", "--out", tmp_path / "never.json")
    assert code == 2 and words in err, err
    assert not (tmp_path / "never.json").exists()
