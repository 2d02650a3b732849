"""Issue 44 part 2, absurd model files: models within the schema's bounds drew heights of 1e6 to
1e14 um (psd_um4 1e30, IAAFT quantiles of +-1e9 um, weights of 1e12, variance and noise of
1e12). A model may imply no height beyond the readers' 1 m
(roughgp.surface_models.height_bound), checked when the file is read and before drawing; the
measured-psd model's noise_variance_um2 (ignored by simulate and check, used by fill) must be
0: its noise is part of its PSD."""

from __future__ import annotations

import copy
import json

import numpy as np
import pytest

import roughgp
from roughgp.surface_models.height_bound import HEIGHT_LIMIT_UM, extreme_height
from roughgp.surface_models.model import FittedModel, ModelFileError
from model_records import EQ18_RECORD, EQ21_RECORD


@pytest.fixture(scope="module")
def fitted():
    z = np.random.default_rng(3).normal(size=(24, 24))
    return {"psd": roughgp.fit(z, 1.0, model="psd").to_dict(),
            "iaaft": roughgp.fit(z, 1.0, marginal="iaaft", block=8, n_blocks=4).to_dict()}


def _spoiled(record, path, value):
    record = copy.deepcopy(record)
    *parents, last = path
    target = record
    for key in parents:
        target = target[key]
    target[last] = value(target[last]) if callable(value) else value
    return record


CASES = [
    ("eq18", ("hyperparameters", "variance_um2"), 1e12, "variance_um2"),
    ("eq18", ("hyperparameters", "noise_variance_um2"), 1e12, "noise_variance_um2"),
    ("eq18", ("hyperparameters", "mean_um"), 1e9, "mean_um"),
    ("eq21", ("hyperparameters", "weights_um2"), [1e12], "weights_um2"),
    ("psd", ("hyperparameters", "psd_um4"), lambda rows: [[1e30] * len(r) for r in rows],
     "psd_um4"),
    ("iaaft", ("marginal", "quantiles_um"), lambda q: np.linspace(-1e9, 1e9, len(q)).tolist(),
     "quantiles_um"),
]


@pytest.mark.parametrize("name, path, value, field", CASES, ids=[c[-1] for c in CASES])
def test_a_model_implying_heights_beyond_a_metre_is_refused_on_reading(fitted, name, path,
                                                                       value, field):
    base = {"eq18": EQ18_RECORD, "eq21": EQ21_RECORD, **fitted}[name]
    record = _spoiled(base, path, value)
    if name == "eq21":
        record["hyperparameters"].update(frequencies_per_um=[0.1],
                                         spectral_variances_per_um2=[1e-4])
    with pytest.raises(ModelFileError) as info:
        FittedModel.from_dict(record)
    message = str(info.value)
    assert field in message and "1e+06 um (1 m)" in message and "at most" in message


def test_fitted_models_stay_far_inside_the_bound(fitted):
    for record in (EQ18_RECORD, EQ21_RECORD, *fitted.values()):
        model = FittedModel.from_dict(record)
        assert extreme_height(model)[0] < 1e-3 * HEIGHT_LIMIT_UM


def test_a_model_built_in_memory_is_checked_before_drawing():
    model = FittedModel.from_dict(EQ18_RECORD)
    huge = FittedModel(model.equation, {**model.hyperparameters, "variance_um2": 1e11},
                       model.spacing)
    with pytest.raises(ModelFileError, match="variance_um2"):
        huge.simulate((8, 8), seed=0)


def test_a_measured_psd_model_with_noise_is_refused(fitted):
    record = _spoiled(fitted["psd"], ("hyperparameters", "noise_variance_um2"), 0.5)
    with pytest.raises(ModelFileError, match="noise_variance_um2 of a measured-psd model must "
                                             "be 0"):
        FittedModel.from_dict(record)


def test_simulate_from_an_absurd_file_exits_2_and_writes_nothing(tmp_path, capsys):
    from roughgp.cli.main import main
    path, out = tmp_path / "huge.json", tmp_path / "o.npy"
    path.write_text(json.dumps(_spoiled(EQ18_RECORD, ("hyperparameters", "variance_um2"),
                                        1e12)))
    code = main(["simulate", "--from", str(path), "--shape", "8", "8", "--seed", "0", "--out",
                 str(out)])
    err = capsys.readouterr().err
    assert code == 2 and "variance_um2" in err and "Traceback" not in err
    assert not out.exists()
