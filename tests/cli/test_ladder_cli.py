"""``roughgp fit ground --model eq18|matern|sm|psd|auto`` and ``--marginal``: the ladder of models
on the command line, and its models read by ``simulate --from``, ``check`` and ``fill
--model``."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from roughgp.checking.model_check import SURFACE_PARAMETERS
from roughgp.gp.kernels import RotatedExponentialKernel
from roughgp.io import x3p
from roughgp.io.writers import write_heights
from roughgp.surface_models.model import FittedModel
from roughgp.sampling import sample_grid
from cli_run import run


@pytest.fixture(scope="module")
def surface(tmp_path_factory):
    """An eq 18 surface, 96 x 96 at 0.5 um, lognormal heights, with a hole."""
    kernel = RotatedExponentialKernel(1.0, (4.0, 1.5), math.radians(30))
    z = np.exp(0.6 * sample_grid(kernel, (96, 96), spacing=0.5, seed=4)[0])
    z[30:40, 50:64] = np.nan
    path = tmp_path_factory.mktemp("ladder") / "s.x3p"
    write_heights(path, z, 0.5, "test surface")
    return path


def test_psd_model_with_iaaft_through_simulate_check_and_fill(capsys, tmp_path, surface):
    model = tmp_path / "psd.json"
    record, out = _fit(capsys, surface, model, "--model", "psd", "--marginal", "iaaft",
                       "--l-filter", "none")
    assert record["equation"] == "measured-psd" and record["marginal"]["method"] == "iaaft"
    assert "measured PSD" in out and "IAAFT" in out
    outside = _through_simulate_check_and_fill(capsys, tmp_path, model, surface)
    assert len(outside) <= 4, outside  # its own measurement: few outside


def _fit(capsys, surface, model, *options):
    """``fit ground surface *options --out model``: it succeeds; the model file's record and
    what the command printed."""
    code, out, err = run(capsys, "fit", "ground", surface, *options, "--out", model)
    assert code == 0, err
    return json.loads(model.read_text()), out


def _through_simulate_check_and_fill(capsys, tmp_path, model, surface):
    """``simulate --from``, ``check`` and ``fill --model`` of ``model``: each runs; the
    parameters the check leaves outside."""
    sim = tmp_path / "sim.x3p"
    code, _, err = run(capsys, "simulate", "--from", model, "--shape", 40, 70, "--seed", 2,
                       "--out", sim)
    assert code == 0, err
    assert x3p.read_x3p(sim).z.shape == (40, 70)
    code, out, err = run(capsys, "check", model, surface, "--simulations", 9, "--json",
                         tmp_path / "c.json")
    assert code == 0, err
    code, out, err = run(capsys, "fill", surface, "--model", model, "--out",
                         tmp_path / "filled.x3p")
    assert code == 0, err
    filled = x3p.read_x3p(tmp_path / "filled.x3p").z
    assert np.isfinite(filled).all()
    return json.loads((tmp_path / "c.json").read_text())["outside"]


def test_sm_model_with_johnson_through_simulate_check_and_fill(capsys, tmp_path, surface):
    model = tmp_path / "sm.json"
    record, out = _fit(capsys, surface, model, "--model", "sm", "--marginal", "johnson",
                       "--l-filter", "none")
    assert record["equation"] == "sm2d" and set(record["marginal"]) == {"skewness", "kurtosis"}
    assert "2-D spectral mixture: Q = " in out
    outside = _through_simulate_check_and_fill(capsys, tmp_path, model, surface)
    assert set(outside) <= set(SURFACE_PARAMETERS), outside   # a verdict on the 13 names
    narrow = dict(record, hyperparameters={**record["hyperparameters"],
                                           "bandwidths_a_per_um": [1e-3] * len(
                                               record["hyperparameters"]["weights_um2"])})
    (tmp_path / "narrow.json").write_text(json.dumps(narrow))
    code, _, err = run(capsys, "simulate", "--from", tmp_path / "narrow.json", "--shape", 4000,
                       4000, "--seed", 0, "--out", tmp_path / "n.npy")
    assert code == 2 and "torus of about" in err and "Traceback" not in err


def test_auto_prints_each_candidate_and_why(capsys, tmp_path, surface):
    model = tmp_path / "auto.json"
    record, out = _fit(capsys, surface, model, "--model", "auto", "--blocks", "4")
    lines = [line.split() for line in out.splitlines()]
    scored = {w[0]: float(w[1]) for w in lines if w and w[0] in ("eq18", "matern", "sm",
                                                                  "psd")}
    assert set(scored) == {"eq18", "matern", "sm", "psd"} and all(v > 0 for v in
                                                                 scored.values())
    assert "chose " in out
    chosen = {"eq18": "eq18", "eq18-matern": "matern", "sm2d": "sm", "measured-psd": "psd"}[
        record["equation"]]
    assert f"chose {chosen}" in out and "chosen_by" in record["fit"]
    assert set(record["fit"]["held_out_rmse_um"]) == {"eq18", "matern", "sm", "psd"}
    # the heights by the out-of-sample check: lognormal heights are not left Gaussian
    checked = {w[0]: int(w[1]) for w in lines if len(w) > 2 and w[0] in
               ("gaussian", "johnson", "iaaft")}
    assert checked == record["fit"]["out_of_sample_outside"] and len(checked) == 3
    assert "checking the heights' distribution out of sample" in out
    heights = FittedModel.load(model).marginal_method
    assert heights != "gaussian" and checked[heights] == min(checked.values())
    assert f"with {heights} heights: they leave the fewest" in " ".join(out.split())


def test_matern_rung_and_bad_combinations(capsys, tmp_path, surface):
    record, _ = _fit(capsys, surface, tmp_path / "m.json", "--model", "matern", "--blocks", "4")
    assert record["equation"] == "eq18-matern" and record["hyperparameters"]["nu"] == 1.5
    code, _, err = run(capsys, "fit", "ground", surface, "--non-gaussian", "--marginal",
                       "iaaft")
    assert code == 2 and "--non-gaussian is --marginal johnson" in err
    code, _, err = run(capsys, "fit", "ground", surface, "--model", "spline")
    assert code == 2 and "invalid choice: 'spline'" in err
