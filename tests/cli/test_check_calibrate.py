"""``roughgp check --calibrate B`` (issue 29): the calibrated column and verdicts, the JSON
record, and the refusals (a model it cannot refit, B out of range) before any work."""

from __future__ import annotations

import dataclasses
import json

import numpy as np
import pytest

from roughgp.experiments.model_check import synthetic_measurement
from roughgp.surface_models.fit import fit_surface_model
from cli_run import run as _run


@pytest.fixture(scope="module")
def fitted_case():
    truth, l_filter, z = synthetic_measurement(3, (40, 40), 0)
    model = fit_surface_model(z, 1.0, l=l_filter, block=12, n_blocks=6, seed=5).model
    return model, z


def test_check_calibrate_on_the_command_line(capsys, tmp_path, fitted_case):
    model, z = fitted_case
    np.save(tmp_path / "m.npy", z)
    model.save(tmp_path / "m.json")
    out = tmp_path / "c.json"
    code, text, err = _run(capsys, "check", tmp_path / "m.json", tmp_path / "m.npy",
                           "--simulations", 4, "--calibrate", 2, "--json", out)
    assert code == 0, err
    assert "p (cal.)" in text and "calibrated by 2 refitted bootstrap copies" in text
    assert "bootstrap copy 2/2" in err
    assert "called outside only with probability 0.3" in err  # 2 copies: (2 + 1) / 10
    assert json.loads(out.read_text())["calibration"]["n_bootstrap"] == 2
    dataclasses.replace(model, stage="filtered").save(tmp_path / "f.json")
    code, _, err = _run(capsys, "check", tmp_path / "f.json", tmp_path / "m.npy",
                        "--calibrate", 2)
    assert code == 2 and "--calibrate" in err and "form-removed" in err
    code, _, err = _run(capsys, "check", tmp_path / "m.json", tmp_path / "m.npy",
                        "--calibrate", 100)
    assert code == 2 and "--calibrate must be in [1, 99]" in err
