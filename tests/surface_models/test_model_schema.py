"""The model file's schema (roughgp.surface_models.schema): every field refused when of the
wrong type, out of range, missing, unknown or nested too deep, with a message naming it."""

from __future__ import annotations

import copy
import dataclasses
import json

import numpy as np
import pytest

from roughgp.surface_models.model import FittedModel, ModelFileError
from roughgp.surface_models.schema import MAX_FILE_BYTES

EQ18 = FittedModel("eq18", {"variance_um2": 2.0, "lambda_a_um": 12.0, "lambda_b_um": 3.0,
                            "angle_deg": 60.0, "noise_variance_um2": 0.05, "mean_um": 0.1},
                   (1.0, 1.0), marginal={"skewness": 0.5, "kurtosis": 4.0},
                   operators=("F: plane", "L: Gaussian 25 um"),
                   cutoffs={"form": "plane", "s_um": None, "l_um": 25.0, "degree": 2,
                            "axis": "auto"}, data={"file": "x.x3p"}, fit={"seed": 0})
EQ21 = FittedModel("eq21", {"weights_um2": [1.0, 0.5], "frequencies_per_um": [0.1, 0.02],
                            "spectral_variances_per_um2": [1e-4, 1e-5],
                            "noise_variance_um2": 0.01}, (0.5,))


def _set(record, path, value):
    record = copy.deepcopy(record)
    *parents, last = path
    target = record
    for key in parents:
        target = target[key]
    if value is _DELETE:
        del target[last]
    else:
        target[last] = value
    return record


class _Delete:
    def __repr__(self):  # a stable test id (an object's default repr carries its address)
        return "<deleted>"


_DELETE = _Delete()

HOSTILE = [
    # (path, value, words of the message)
    (("format",), "roughgp-mode", "not a roughgp model file"),
    (("version",), True, "version True"),
    (("version",), 3, "version 3"),
    (("version",), "2", "version '2'"),
    (("version",), _DELETE, "version None"),
    (("equation",), "eq99", "equation must be one of"),
    (("equation",), ["eq18"], "equation must be one of"),
    (("equation",), _DELETE, "lacks the field(s) equation"),
    (("stage",), "raw", "stage must be one of"),
    (("stage",), None, "stage must be one of"),
    (("stage",), _DELETE, "lacks the field(s) stage"),
    (("kind",), "profile", "does not match"),
    (("description",), 5, "description must be a string"),
    (("surprise",), 1, "unknown field(s) surprise"),
    (("hyperparameters",), [1, 2], "hyperparameters must be an object"),
    (("hyperparameters", "variance_um2"), True, "variance_um2 must be a number"),
    (("hyperparameters", "variance_um2"), "2.0", "variance_um2 must be a number"),
    (("hyperparameters", "variance_um2"), 0.0, "variance_um2 must be a finite number in (0"),
    (("hyperparameters", "variance_um2"), 1e300, "variance_um2 must be a finite number"),
    (("hyperparameters", "variance_um2"), None, "variance_um2 must be a number"),
    (("hyperparameters", "variance_um2"), {"a": 1}, "variance_um2 must be a number"),
    (("hyperparameters", "variance_um2"), _DELETE, "lacks variance_um2"),
    (("hyperparameters", "noise_variance_um2"), -1.0, "noise_variance_um2 must be a finite"),
    (("hyperparameters", "noise_variance_um2"), 1e13, "noise_variance_um2 must be a finite"),
    (("hyperparameters", "lambda_a_um"), -1.0, "lambda_a_um must be a finite number"),
    (("hyperparameters", "lambda_a_um"), 5e7, "lambda_a_um must be within"),
    (("hyperparameters", "lambda_b_um"), 1e-9, "lambda_b_um must be within"),
    (("hyperparameters", "angle_deg"), 1e4, "angle_deg must be a finite number"),
    (("hyperparameters", "angle_deg"), False, "angle_deg must be a number"),
    (("hyperparameters", "mean_um"), "0", "mean_um must be a number"),
    (("hyperparameters", "nu"), 1.5, "unknown hyperparameters nu"),
    (("spacing_um",), [1.0], "spacing_um must hold 2 values"),
    (("spacing_um",), [1.0, 0.0], "spacing_um[1] must be a finite number in [1e-06, 1e+06]"),
    # issue 44 part 2: 1e-300 was blamed on lambda_a_um
    (("spacing_um",), [1e-300, 1.0], "spacing_um[0] must be a finite number in [1e-06, 1e+06]"),
    (("spacing_um",), [1.0, True], "spacing_um[1] must be a number"),
    (("spacing_um",), 1.0, "spacing_um must be a non-empty list"),
    (("spacing_um",), _DELETE, "lacks the field(s) spacing_um"),
    (("marginal",), {"skewness": 0.5}, "marginal must be null, "),
    (("marginal",), {"skewness": 0.5, "kurtosis": 4.0, "x": 1}, "marginal must be null, "),
    (("marginal", "kurtosis"), 1.1, "kurtosis must be > skewness**2 + 1"),
    (("marginal", "skewness"), "big", "skewness must be a number"),
    (("marginal", "kurtosis"), 1e9, "kurtosis must be a finite number"),
    (("cutoffs",), "25", "cutoffs must be an object"),
    (("cutoffs", "l_um"), "25 um", "cutoffs.l_um must be a number"),
    (("cutoffs", "l_um"), -25.0, "cutoffs.l_um must be a finite number"),
    (("cutoffs", "l_um"), True, "cutoffs.l_um must be a number"),
    (("cutoffs", "s_um"), 30.0, "cutoffs.s_um must be smaller than cutoffs.l_um"),
    (("cutoffs", "form"), "sphere", "cutoffs.form must be one of"),
    (("cutoffs", "degree"), 2.5, "cutoffs.degree must be an integer"),
    (("cutoffs", "axis"), "z", "cutoffs.axis must be one of"),
    (("cutoffs", "lc"), 8.0, "cutoffs has unknown fields lc"),
    (("operators",), "F: plane", "operators must be a list"),
    (("operators",), [1], "operators must be a list"),
    (("data",), [1], "data must be an object"),
    (("fit",), "x", "fit must be an object"),
    # issue 44 part 2: the fields of fit read back (a calibrated check refits with them)
    (("fit", "seed"), [1], "fit.seed must be an integer in [0, 4294967295]"),
    (("fit", "seed"), True, "fit.seed must be an integer"),
    (("fit", "seed"), -1, "fit.seed must be an integer"),
    (("fit", "block"), "24", "fit.block must be an integer in [4, 1024]"),
    (("fit", "n_blocks"), 1.5, "fit.n_blocks must be an integer"),
    (("fit", "likelihood"), "exact", "fit.likelihood must be one of"),
    (("data", "deep"), [[[[[[[[[1]]]]]]]]], "nested deeper"),
]


@pytest.mark.parametrize("path, value, message", HOSTILE,
                         ids=[f"{'.'.join(p)}={v!r}"[:40] for p, v, _ in HOSTILE])
def test_every_field_of_a_hostile_file_is_refused_by_name(tmp_path, path, value, message):
    record = _set(EQ18.to_dict(), path, value)
    file = tmp_path / "m.json"
    file.write_text(json.dumps(record))
    with pytest.raises(ModelFileError) as info:
        FittedModel.load(file)
    assert message in str(info.value)


EQ21_HOSTILE = [
    (("hyperparameters", "weights_um2"), [], "weights_um2 must be a non-empty list"),
    (("hyperparameters", "weights_um2"), [1.0] * 51, "weights_um2 must hold"),
    (("hyperparameters", "weights_um2"), [1.0, 2.0, 3.0], "must have the same length"),
    (("hyperparameters", "frequencies_per_um"), [0.1, -0.1], "frequencies_per_um[1] must be"),
    (("hyperparameters", "spectral_variances_per_um2"), [1e-4, "x"],
     "spectral_variances_per_um2[1] must be a number"),
    (("spacing_um",), [0.5, 0.5], "spacing_um must hold 1 values"),
]


@pytest.mark.parametrize("path, value, message", EQ21_HOSTILE)
def test_a_hostile_profile_model_is_refused_by_name(path, value, message):
    with pytest.raises(ModelFileError) as info:
        FittedModel.from_dict(_set(EQ21.to_dict(), path, value))
    assert message in str(info.value)


def test_a_version_1_file_stating_another_stage_is_refused():
    """Version 1 had no stage (its models describe the filtered heights): a stage
    "form-removed" in it was silently replaced by "filtered"."""
    record = {**EQ18.to_dict(), "version": 1, "stage": "form-removed"}
    with pytest.raises(ModelFileError, match="version 1.*form-removed.*\"version\": 2"):
        FittedModel.from_dict(record)
    assert FittedModel.from_dict({**record, "stage": "filtered"}).stage == "filtered"


def test_good_files_round_trip_and_nan_or_huge_files_are_refused(tmp_path):
    for model in (EQ18, EQ21):
        assert FittedModel.load(model.save(tmp_path / "m.json")) == model
    file = tmp_path / "nan.json"
    file.write_text(json.dumps(EQ18.to_dict()).replace('"variance_um2": 2.0',
                                                       '"variance_um2": NaN'))
    with pytest.raises(ModelFileError, match="variance_um2 must be a finite number"):
        FittedModel.load(file)
    file.write_text("[" * 100000 + "]" * 100000)
    with pytest.raises(ModelFileError, match="nested"):
        FittedModel.load(file)
    file.write_text(" " * (MAX_FILE_BYTES + 1))
    with pytest.raises(ModelFileError, match="larger than a model file"):
        FittedModel.load(file)


def test_the_cli_refuses_a_hostile_model_with_one_line_and_exit_2(tmp_path, capsys):
    from roughgp.cli.main import main
    file = tmp_path / "m.json"
    file.write_text(json.dumps(_set(EQ18.to_dict(), ("cutoffs", "l_um"), "25 um")))
    code = main(["simulate", "--from", str(file), "--shape", "8", "8", "--seed", "0", "--out",
                 str(tmp_path / "o.npy")])
    err = capsys.readouterr().err
    assert code == 2 and "cutoffs.l_um must be a number" in err and "Traceback" not in err
    assert not (tmp_path / "o.npy").exists()


def test_check_calibrate_of_a_model_with_a_list_seed_exits_2_naming_the_field(tmp_path, capsys):
    """Issue 44 part 2: ``"fit": {"seed": [1]}`` gave a TypeError in the calibrated check."""
    import numpy as np

    from roughgp.cli.main import main
    file, data = tmp_path / "m.json", tmp_path / "z.npy"
    record = {**EQ18.to_dict(), "stage": "form-removed", "fit": {"seed": [1]}}
    file.write_text(json.dumps(record))
    np.save(data, np.random.default_rng(0).normal(size=(16, 16)))
    code = main(["check", str(file), str(data), "--calibrate", "1"])
    err = capsys.readouterr().err
    assert code == 2 and "fit.seed must be an integer" in err and "Traceback" not in err


@pytest.mark.parametrize("model, shape, recorded", [
    (EQ18, [64, 128], (64, 128)),
    (EQ18, [np.int64(64), 32], (64, 32)),  # a fit's numpy sizes, before the file
    (EQ18, [[64, 64], [32, 32]], None),  # several maps
    (EQ18, [64], None),
    (EQ18, [True, 64], None),
    (EQ18, [1, 64], None),
    (EQ18, "64 x 64", None),
    (EQ21, [400], (400,)),
    (EQ21, [1, 400], None),
])
def test_the_recorded_shape_is_the_one_grid_the_file_records_or_none(model, shape, recorded):
    """``FittedModel.recorded_shape``, read by ``simulate --from`` (the size to draw), the
    predictive check (the bootstrap copies' grid) and the measured PSD (its ACVF's grid)."""
    assert dataclasses.replace(model, data={"shape": shape}).recorded_shape == recorded
    assert dataclasses.replace(model, data={}).recorded_shape is None
