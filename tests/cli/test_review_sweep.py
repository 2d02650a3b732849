"""Issue 32's review list, one case each: a clear exit-2 message naming the option (or the
file's field), or a right reading; and nothing written where a command refuses."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from roughgp.cli.main import main
from roughgp.surface_models.model import FittedModel

DATA = Path(__file__).resolve().parents[2] / "data"
MODEL = FittedModel("eq18", {"variance_um2": 2.0, "lambda_a_um": 12.0, "lambda_b_um": 3.0,
                             "angle_deg": 60.0, "noise_variance_um2": 0.05, "mean_um": 0.1},
                    (1.0, 1.0), operators=("F: plane", "L: Gaussian 25 um"),
                    cutoffs={"form": "plane", "s_um": None, "l_um": 25.0, "degree": 2,
                             "axis": "auto"}, data={"file": "x.x3p"}, fit={"seed": 0})


def _run(capsys, *args):
    code = main([str(a) for a in args])
    out, err = capsys.readouterr()
    assert "Traceback" not in err
    return code, out, err


@pytest.fixture()
def holed(tmp_path):
    """A surface with missing points, named H.NPY.npy (a name whose stem ends in .NPY)."""
    z = np.random.default_rng(0).normal(size=(30, 30))
    z[4:7, 4:7] = np.nan
    path = tmp_path / "H.NPY.npy"
    np.save(path, z)
    return path


def test_fill_never_writes_over_its_input(capsys, holed):
    before = holed.read_bytes()
    code, _, err = _run(capsys, "fill", holed, "--out", holed, "--force", "--seed", 1)
    assert code == 2 and "--out" in err and "input" in err
    code, _, _ = _run(capsys, "fill", holed, "--out", holed.with_suffix(""), "--seed", 1)
    assert code == 0 and holed.read_bytes() == before  # H.NPY written, H.NPY.npy untouched
    assert np.load(holed.with_suffix("")).shape == (30, 30)


def test_simulate_twice_without_force(capsys, tmp_path):
    out = tmp_path / "S.NPY"
    assert _run(capsys, "simulate", "ground", "--shape", 8, 8, "--seed", 1, "--out", out)[0] == 0
    code, _, err = _run(capsys, "simulate", "ground", "--shape", 8, 8, "--seed", 2, "--out", out)
    assert code == 2 and "exists" in err and "--force" in err


def test_fit_checks_the_folder_before_fitting(capsys, tmp_path):
    blocker = tmp_path / "a-file"
    blocker.write_text("x")
    code, _, err = _run(capsys, "fit", "ground", DATA / "sample-land.x3p",
                        "--out", blocker / "m.json")
    assert code == 2 and "--out" in err and "not a directory" in err and "fitted" not in err


def test_check_writes_both_outputs_or_neither(capsys, tmp_path):
    model = MODEL.save(tmp_path / "m.json")
    blocker = tmp_path / "a-file"
    blocker.write_text("x")
    code, _, err = _run(capsys, "check", model, DATA / "sample-land.x3p", "--json",
                        tmp_path / "d" / "c.json", "--plot", blocker / "c.png")
    assert code == 2 and "--plot" in err and not (tmp_path / "d").exists()


@pytest.mark.parametrize("path, value, message", [
    (("hyperparameters", "noise_variance_um2"), 1e300, "noise_variance_um2 must be a finite"),
    (("hyperparameters", "variance_um2"), True, "variance_um2 must be a number"),
    (("cutoffs", "l_um"), "abc", "cutoffs.l_um must be a number"),
    (("cutoffs", "form"), "banana", "cutoffs.form must be one of"),
    (("cutoffs",), [1, 2], "cutoffs must be an object"),
])
def test_a_hostile_model_file_is_named(capsys, tmp_path, path, value, message):
    record = json.loads(json.dumps(MODEL.to_dict()))
    target = record
    for key in path[:-1]:
        target = target[key]
    target[path[-1]] = value
    model = tmp_path / "m.json"
    model.write_text(json.dumps(record))
    out = tmp_path / "s.npy"
    code, _, err = _run(capsys, "simulate", "--from", model, "--shape", 8, 8, "--out", out)
    assert code == 2 and message in err and "--from" in err and not out.exists()
    assert "simulate None" not in err  # the prefix of a parser without its kind


@pytest.mark.parametrize("args, option", [
    (["simulate", "ground", "--shape", "8", "8", "--spacing", "1e-300", "--out", "{tmp}/s.npy"],
     "--spacing"),
    (["texture", str(DATA / "sample-land.x3p"), "--l-filter", "1e300"], "--l-filter"),
    (["texture", str(DATA / "opd-1.opd"), "--spacing", "1e-300"], "--spacing"),
    (["fill", str(DATA / "sample-land.x3p"), "--seed", "-1", "--out", "{tmp}/f.x3p"], "--seed"),
])
def test_an_absurd_scale_names_its_option(capsys, tmp_path, args, option):
    code, _, err = _run(capsys, *(a.replace("{tmp}", str(tmp_path)) for a in args))
    assert code == 2 and f"{option} must be" in err and not list(tmp_path.iterdir())


@pytest.mark.parametrize("name, shape, spacing_um, sq_um", [
    ("matrix-3.txt", "256 x 256", 10.0 / 256, (1e-3, 0.1)),  # header: 10 um wide, heights in m
    ("csv-2.csv", "8 points", 0.0833333, None),  # UTF-16, "x in um" in the column header
])
def test_a_text_file_is_read_with_its_headers_units(capsys, name, shape, spacing_um, sq_um):
    code, out, err = _run(capsys, "texture", DATA / name)
    assert code == 0, err
    assert shape in out and f"spacing {spacing_um:.6g}" in out
    if sq_um is not None:  # heights of about 20 nm stated in m: Sq in nm, not in Mm or m
        sq = float(next(line.split()[1] for line in out.splitlines()
                        if line.strip().startswith("Sq ")))
        assert sq_um[0] < sq < sq_um[1]


def test_fill_help_names_the_nanofocus_format(capsys):
    assert main(["fill", "--help"]) == 0
    assert "NanoFocus .nms" in " ".join(capsys.readouterr().out.split())  # however wrapped
