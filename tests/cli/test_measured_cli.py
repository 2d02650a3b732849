"""The loop of ``roughgp fit ground`` -> ``simulate --from`` -> ``check`` on a real measurement
(the striated bullet land of data/), and ``fill --model``; the model options' refusals."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from roughgp.cli.main import main
from roughgp.io import x3p
from cli_run import run as _run

LAND = Path(__file__).resolve().parents[2] / "data" / "sample-land.x3p"


@pytest.fixture(scope="module")
def land_model(tmp_path_factory):
    path = tmp_path_factory.mktemp("model") / "land.json"
    code = main(["fit", "ground", str(LAND), "--form", "cylinder", "--l-filter", "250",
                 "--out", str(path)])
    assert code == 0
    return path


def test_fit_ground_finds_the_striations_of_the_bullet_land(land_model):
    model = json.loads(land_model.read_text())
    hp = model["hyperparameters"]
    assert model["equation"] == "eq18" and model["data"]["file"] == "sample-land.x3p"
    assert len(model["data"]["sha256"]) == 64 and model["data"]["missing_fraction"] > 0.05
    assert any(op.startswith("F: cylinder") for op in model["operators"])
    # the striations run along y: the lay angle is near +-90 degrees from x
    assert abs(abs(hp["angle_deg"]) - 90.0) < 20.0
    assert hp["lambda_a_um"] > hp["lambda_b_um"] > 0


def test_simulate_from_the_model_and_check_it(capsys, tmp_path, land_model):
    out = tmp_path / "new.x3p"
    code, _, err = _run(capsys, "simulate", "--from", land_model, "--shape", 64, 96,
                        "--seed", 3, "--out", out)
    assert code == 0, err
    hm = x3p.read_x3p(out)
    assert hm.z.shape == (64, 96) and np.allclose(hm.spacing, 2.58, rtol=1e-6)
    again = tmp_path / "again.x3p"
    assert _run(capsys, "simulate", "--from", land_model, "--shape", 64, 96, "--seed", 3,
                "--out", again)[0] == 0
    np.testing.assert_array_equal(x3p.read_x3p(again).z, hm.z)
    table, plot = tmp_path / "check.json", tmp_path / "check.png"
    code, out_text, err = _run(capsys, "check", land_model, LAND, "--simulations", 4,
                               "--json", table, "--plot", plot)
    assert code == 0, err
    record = json.loads(table.read_text())
    names = {p["name"] for p in record["parameters"]}
    assert {"Sq", "Ssk", "Sku", "Sal", "Str", "Std"} <= names
    # the data's verdict: the land's heights are heavy-tailed; the Gaussian model cannot be
    assert "Sku" in record["outside"] and "OUTSIDE" in out_text
    assert plot.stat().st_size > 10_000


def test_fill_with_the_model_file(capsys, tmp_path, land_model):
    out, sd = tmp_path / "filled.npy", tmp_path / "sd.npy"
    code, _, err = _run(capsys, "fill", LAND, "--model", land_model, "--form", "cylinder",
                        "--out", out, "--sd", sd)
    assert code == 0, err
    z = x3p.read_x3p(LAND).z
    filled, spread = np.load(out), np.load(sd)
    missing = np.isnan(z)
    assert np.all(np.isfinite(filled)) and np.all(spread[missing] > 0)
    np.testing.assert_allclose(filled[~missing], z[~missing] * 1.0, rtol=0, atol=1e-9)
    assert "moving-window kriging" in err


def test_simulate_from_a_model_without_shape_draws_the_size_it_was_fitted_on(capsys, tmp_path,
                                                                              land_model):
    out = tmp_path / "same-size.npy"
    code, _, err = _run(capsys, "simulate", "--from", land_model, "--seed", 3, "--out", out)
    assert code == 0, err
    fitted = json.loads(land_model.read_text())["data"]["shape"]
    assert list(np.load(out).shape) == fitted == list(x3p.read_x3p(LAND).z.shape)
    assert f"--shape not given: {fitted[0]} x {fitted[1]} points, the size of the surface" in err


@pytest.mark.parametrize("argv, message", [
    (("simulate", "--shape", 4, 4, "--out", "x.npy"), "give a KIND"),
    (("simulate", "--from", "SIZELESS", "--out", "x.npy"), "the size is missing: give --shape"),
    (("simulate", "--from", "MODEL", "--shape", 1, 40, "--out", "x.npy"), "surface model"),
    (("simulate", "--from", "nothere.json", "--shape", 4, 4, "--out", "x.npy"),
     "no such model file"),
    (("check", "MODEL", "LAND", "--simulations", 1), "--simulations must be in [2, 99]"),
    (("check", "MODEL", "LAND", "--plot", "fig.gif"), "--plot"),
    (("fit", "ground", "LAND", "--block", 2), "--block must be in [4, 32]"),
    (("fit", "profile", "LAND", "--mixtures", 1000), "--mixtures must be in [1, 50]"),
    (("fill", "LAND", "--out", "f.npy", "--model", "NOTMODEL"), "not a roughgp model file"),
    (("fill", "LAND", "--out", "f.npy", "--model", "MODEL", "--nu", "auto"),
     "--nu auto chooses the smoothness of a fit; --model has its own"),
])
def test_model_commands_refuse_bad_input(capsys, tmp_path, land_model, argv, message):
    bogus = tmp_path / "bogus.json"
    bogus.write_text("{}")
    sizeless = json.loads(land_model.read_text())
    del sizeless["data"]["shape"]  # a file that does not say the size it was fitted on
    (tmp_path / "sizeless.json").write_text(json.dumps(sizeless))
    swap = {"MODEL": land_model, "LAND": LAND, "NOTMODEL": bogus,
            "SIZELESS": tmp_path / "sizeless.json"}
    argv = [swap.get(a, a) if isinstance(a, str) else a for a in argv]
    argv = [str(tmp_path / a) if isinstance(a, str) and a.endswith((".npy", ".gif"))
            and not Path(a).is_absolute() else a for a in argv]
    code, _, err = _run(capsys, *argv)
    assert code == 2 and message in err and "Traceback" not in err
