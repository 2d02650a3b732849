"""No command writes over its input; writing over another existing file needs ``--force``; the
extension matches the content; outputs are checked before any computation (issue 18, "A
user's file is lost")."""

from __future__ import annotations

import time

import numpy as np
import pytest

from roughgp.io import x3p
from cli_run import run as _run


@pytest.fixture
def surface(tmp_path):
    """A 12 x 16 x3p surface with two missing points."""
    z = np.random.default_rng(0).normal(size=(12, 16))
    z[3, 4] = z[7, 9] = np.nan
    path = tmp_path / "holes.x3p"
    x3p.write_x3p(path, z, 1.0)
    return path


@pytest.fixture
def profile(tmp_path):
    path = tmp_path / "t.csv"
    x = np.arange(64) * 0.5
    np.savetxt(path, np.column_stack((x, np.sin(x))), delimiter=",", fmt="%.6f")
    return path


def _unchanged(path):
    before = path.read_bytes()
    return lambda: path.read_bytes() == before


@pytest.mark.parametrize("how", ["same", "relative"])
def test_fill_never_writes_over_its_input(capsys, surface, how, monkeypatch):
    same = _unchanged(surface)
    out = surface
    if how == "relative":
        monkeypatch.chdir(surface.parent)
        out = f"./{surface.name}"
    for extra in ([], ["--force"]):
        code, _, err = _run(capsys, "fill", surface, "--out", out, *extra)
        assert code == 2 and "is the input file" in err and "--out" in err, err
    assert same()


def test_fill_sd_never_writes_over_the_input(capsys, surface, tmp_path):
    same = _unchanged(surface)
    code, _, err = _run(capsys, "fill", surface, "--out", tmp_path / "o.npy", "--sd", surface)
    assert code == 2 and "--sd" in err and "is the input file" in err
    assert same() and not (tmp_path / "o.npy").exists()


def test_fill_out_and_sd_must_differ(capsys, surface, tmp_path):
    code, _, err = _run(capsys, "fill", surface, "--out", tmp_path / "a.npy",
                        "--sd", tmp_path / "a.npy")
    assert code == 2 and "--sd and --out name the same file" in err
    assert not (tmp_path / "a.npy").exists()


def test_texture_json_never_writes_over_its_input(capsys, profile):
    same = _unchanged(profile)
    code, _, err = _run(capsys, "texture", profile, "--json", profile, "--force")
    assert code == 2 and "--json" in err and ".json" in err
    assert same()
    as_json = profile.with_suffix(".json")
    profile.rename(as_json)                       # an input whose name ends in .json
    code, _, err = _run(capsys, "texture", as_json, "--json", as_json, "--force")
    assert code == 2 and "is the input file" in err


def test_fit_never_writes_over_its_input(capsys, profile):
    same = _unchanged(profile)
    code, _, err = _run(capsys, "fit", "profile", profile, "--out", profile)
    assert code == 2 and "--out" in err and "writes JSON" in err
    assert same()


def test_fit_out_must_be_json(capsys, profile, tmp_path):
    code, _, err = _run(capsys, "fit", "profile", profile, "--out", tmp_path / "fit.npy")
    assert code == 2 and "writes JSON" in err and ".json" in err
    assert not (tmp_path / "fit.npy").exists()


def test_simulate_needs_force_to_write_over_a_file(capsys, tmp_path):
    path = tmp_path / "g.npy"
    np.save(path, np.zeros(3))
    same = _unchanged(path)
    argv = ("simulate", "ground", "--shape", 8, 8, "--seed", 1, "--out", path)
    code, _, err = _run(capsys, *argv)
    assert code == 2 and "exists" in err and "--force" in err and "drawing" not in err
    assert same()
    code, _, err = _run(capsys, *argv, "--force")
    assert code == 0, err
    assert np.load(path).shape == (8, 8)


def test_texture_and_fit_need_force_to_write_over_a_json(capsys, profile, tmp_path):
    target = tmp_path / "r.json"
    target.write_text("{}\n")
    code, _, err = _run(capsys, "texture", profile, "--json", target)
    assert code == 2 and "--json" in err and "--force" in err
    assert target.read_text() == "{}\n"
    code, _, err = _run(capsys, "texture", profile, "--json", target, "--force")
    assert code == 0, err
    assert "parameters" in target.read_text()
    code, _, err = _run(capsys, "fit", "profile", profile, "--out", target, "--mixtures", 1)
    assert code == 2 and "--out" in err and "--force" in err and "fitting" not in err


def test_fill_needs_force_to_write_over_a_file(capsys, surface, tmp_path):
    target = tmp_path / "filled.npy"
    np.save(target, np.zeros(2))
    code, _, err = _run(capsys, "fill", surface, "--out", target)
    assert code == 2 and "exists" in err and "--force" in err
    assert np.load(target).shape == (2,)


def test_an_unwritable_output_is_refused_before_the_computation(capsys, surface, tmp_path):
    blocker = tmp_path / "a-file"
    blocker.write_text("x")
    start = time.perf_counter()
    code, _, err = _run(capsys, "fill", surface, "--out", blocker / "filled.x3p")
    assert code == 2 and "--out" in err and "not a directory" in err
    assert "fitted" not in err and time.perf_counter() - start < 5
    code, _, err = _run(capsys, "texture", surface, "--json", blocker / "t.json")
    assert code == 2 and "--json" in err and "not a directory" in err
    code, _, err = _run(capsys, "simulate", "turned", "--profile", 64, "--seed", 1,
                        "--out", blocker / "p.csv")
    assert code == 2 and "not a directory" in err and "drawing" not in err
