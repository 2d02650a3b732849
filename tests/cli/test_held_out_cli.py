"""``roughgp fit ground --part`` and ``roughgp check --held-out / --part / --predictive /
--tiles`` (issue 40): the part recorded in the model file, the two tables side by side, the
tile map, and the refusals before any work."""

from __future__ import annotations

import json
import re

import numpy as np
import pytest

from roughgp.experiments.held_out import synthetic_map
from cli_run import run as _run


@pytest.fixture(scope="module")
def left_fit(tmp_path_factory):
    """A 32 x 64 map three times rougher on its right half, and a model of its left half."""
    folder = tmp_path_factory.mktemp("held_out")
    z, _, _ = synthetic_map("stationary", 4, shape=(32, 64))
    z = z.copy()
    z[:, 32:] *= 3.0
    np.save(folder / "map.npy", z)
    code = _main("fit", "ground", folder / "map.npy", "--part", "left", "--block", 12,
                 "--blocks", 4, "--l-filter", "none", "--out", folder / "left.json")
    assert code == 0
    return folder


def _main(*argv):
    from roughgp.cli.main import main
    return main([str(a) for a in argv])


def test_fit_part_records_the_part_and_fits_on_it_alone(left_fit):
    record = json.loads((left_fit / "left.json").read_text())
    assert record["data"]["part"]["name"] == "left"
    assert record["data"]["part"]["cols"] == [0, 32]
    assert record["data"]["shape"] == [32, 32]


def test_check_held_out_says_no_on_the_rougher_half(capsys, left_fit):
    out = left_fit / "held.json"
    code, text, err = _run(capsys, "check", left_fit / "left.json", left_fit / "map.npy",
                           "--held-out", "--simulations", 9, "--json", out)
    assert code == 0, err
    assert "fitted part (left: rows 0:32, columns 0:32)" in text
    assert "held out part (right: rows 0:32, columns 32:64)" in text
    record = json.loads(out.read_text())
    assert "Sq" in record["held_out"]["outside"]
    assert "Sq" not in record["fitted"]["outside"]
    assert "held-\n" not in text


def test_check_tiles_maps_the_rough_side(capsys, left_fit, tmp_path):
    code, text, err = _run(capsys, "check", left_fit / "left.json", left_fit / "map.npy",
                           "--tiles", 1, 4, "--simulations", 9, "--plot", tmp_path / "t.png",
                           "--json", tmp_path / "t.json")
    assert code == 0, err
    assert "Sq   2 of 4 tiles outside" in text or "Sq   3 of 4 tiles outside" in text
    assert ". . + +" in text or "- . + +" in text or ". - + +" in text
    assert (tmp_path / "t.png").stat().st_size > 0
    assert json.loads((tmp_path / "t.json").read_text())["tiles"] == [1, 4]


def test_check_part_and_predictive(capsys, left_fit):
    code, text, err = _run(capsys, "check", left_fit / "left.json", left_fit / "map.npy",
                           "--part", "0:32,40:64", "--predictive", 2, "--simulations", 4)
    assert code == 0, err
    assert "(part 0:32,40:64) against 4 predictive simulations" in text
    assert "bootstrap measurement 2/2 refitted" in err


@pytest.mark.parametrize("options, words", [
    (("--held-out", "--part", "right"), "give one of them"),
    (("--held-out", "--tiles", 2, 2), "cannot be combined with --held-out"),
    (("--calibrate", 2, "--tiles", 2, 2), "cannot be combined with --tiles"),
    (("--part", "0:40,0:20"), "--part '0:40,0:20': rows must lie in 0:32"),
    (("--part", "middle"), "--part must be one of left, right, top, bottom"),
    (("--tiles", 3, 1), "--tiles must be (m, n) with m in [1, 2] and n in [1, 4]"),
    (("--predictive", 100), "--predictive must be in [1, 99]"),
    (("--predictive-from", "sandwich"), "give --predictive B too"),
    (("--predictive", 2, "--predictive-from", "delta"), "--predictive-from: invalid choice"),
])
def test_bad_out_of_sample_options_are_refused_before_any_work(capsys, left_fit, options,
                                                               words):
    code, _, err = _run(capsys, "check", left_fit / "left.json", left_fit / "map.npy", *options)
    assert code == 2 and words in err, err
    assert "simulating" not in err


def test_check_predictive_from_the_sandwich_draws_no_refits(capsys, left_fit):
    code, text, err = _run(capsys, "check", left_fit / "left.json", left_fit / "map.npy",
                           "--held-out", "--predictive", 5, "--predictive-from", "sandwich",
                           "--simulations", 9)
    assert code == 0, err
    assert "against 9 predictive (sandwich) simulations" in text
    assert "drawing 5 parameter sets of the model from its Whittle sandwich covariance on the " \
           "fitted 32 x 32 grid" in err
    assert "refitted" not in err
    again = _run(capsys, "check", left_fit / "left.json", left_fit / "map.npy", "--held-out",
                 "--predictive", 5, "--predictive-from", "sandwich", "--simulations", 9)
    assert again[1] == text


def test_held_out_needs_a_model_fitted_on_a_part(capsys, left_fit, tmp_path):
    record = json.loads((left_fit / "left.json").read_text())
    del record["data"]["part"]
    (tmp_path / "whole.json").write_text(json.dumps(record))
    code, _, err = _run(capsys, "check", tmp_path / "whole.json", left_fit / "map.npy",
                        "--held-out")
    assert code == 2 and "fit it with --part left" in err


def test_fit_whittle_is_recorded_and_refitted_alike(capsys, left_fit, tmp_path):
    from roughgp.checking.predictive import bootstrap_models
    from roughgp.surface_models.model import FittedModel
    code, text, err = _run(capsys, "fit", "ground", left_fit / "map.npy", "--part", "left",
                           "--likelihood", "whittle", "--l-filter", "none",
                           "--out", tmp_path / "w.json")
    assert code == 0, err
    assert "debiased Whittle log likelihood" in text and "all 1024 measured points" in text
    model = FittedModel.load(tmp_path / "w.json")
    assert model.fit["likelihood"] == "whittle"
    refit, = bootstrap_models(model, 1, seed=0)
    assert refit.fit["likelihood"] == "whittle"
    code, _, err = _run(capsys, "fit", "ground", left_fit / "map.npy", "--likelihood", "exact")
    assert code == 2 and "--likelihood" in err and "'blocks', 'whittle'" in err


def test_fit_whittle_on_the_cpu_device_is_the_same_fit(capsys, left_fit, tmp_path):
    """``--device cpu`` runs the Whittle fit's torch code on the CPU: the same model file's
    numbers as without it (the CUDA path is compared in tests/common/test_device.py)."""
    from roughgp.surface_models.model import FittedModel
    outputs = []
    for name, extra in (("plain", ()), ("cpu", ("--device", "cpu"))):
        code, _, err = _run(capsys, "fit", "ground", left_fit / "map.npy", "--part", "left",
                            "--likelihood", "whittle", "--l-filter", "none", *extra,
                            "--out", tmp_path / f"{name}.json")
        assert code == 0, err
        outputs.append(FittedModel.load(tmp_path / f"{name}.json").hyperparameters)
    assert outputs[0] == pytest.approx(outputs[1], rel=1e-6)


@pytest.mark.parametrize("extra, words", [
    ((), "--device applies to --model eq18 with --likelihood whittle and to --model field"),
    (("--likelihood", "whittle", "--model", "matern"), "got --model matern"),
    (("--likelihood", "whittle", "--device", "gpu"), "--device must be None"),
])
def test_fit_device_is_refused_where_it_does_not_apply(capsys, left_fit, tmp_path, extra, words):
    device = () if "--device" in extra else ("--device", "cpu")
    code, _, err = _run(capsys, "fit", "ground", left_fit / "map.npy", *device, *extra,
                        "--out", tmp_path / "never.json")
    assert code == 2 and words in err, err
    assert not (tmp_path / "never.json").exists()


def test_predictive_from_tiles_needs_the_held_out_check_and_tiles_of_16_points(capsys, left_fit):
    code, _, err = _run(capsys, "check", left_fit / "left.json", left_fit / "map.npy",
                        "--predictive", 2, "--predictive-from", "tiles")
    assert code == 2 and "--predictive-from tiles draws the tiles of the part" in err
    assert "give --held-out" in err and "simulating" not in err
    code, _, err = _run(capsys, "check", left_fit / "left.json", left_fit / "map.npy",
                        "--held-out", "--predictive", 2, "--predictive-from", "tiles")
    assert code == 2 and "4 x 4 tiles of a 32 x 32 map are shorter than 16 points" in err, err
    assert "simulating" not in err


def test_check_predictive_from_tiles_of_the_fitted_part(capsys, tmp_path):
    """A measured-psd model with the measured heights, fitted on the left half of a 64 x 128
    map: its tile-bootstrap check runs, says so, and the same seed gives the same table."""
    z, _, _ = synthetic_map("stationary", 3, shape=(64, 128))
    np.save(tmp_path / "map.npy", z)
    code = _main("fit", "ground", tmp_path / "map.npy", "--part", "left", "--model", "psd",
                 "--marginal", "iaaft", "--l-filter", "none", "--out", tmp_path / "left.json")
    assert code == 0
    options = (tmp_path / "left.json", tmp_path / "map.npy", "--held-out", "--predictive", 9,
               "--predictive-from", "tiles", "--simulations", 9)
    code, text, err = _run(capsys, "check", *options)
    assert code == 0, err
    assert "against 9 predictive (tiles) simulations" in text
    assert "drawing 9 models from the fitted part's tiles" in err
    assert re.search(r"the tiles' variance ratios raised to \d\.\d\d: on the model's own", err)
    again = _run(capsys, "check", *options)[1]
    assert again.split(" against ", 1)[1] == text.split(" against ", 1)[1]
