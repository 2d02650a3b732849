"""Tests of the ``roughgp`` command (roughgp.cli), run in-process through ``main(argv)``.

Grids are small (ground and honed 16 x 24: the exact Cholesky sampler; turned 32 x 48) and
the fit uses a 1024-point profile with Q = 2, so the file runs in well under a minute.
"""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from roughgp import ledger
from roughgp.cli.main import main
from roughgp.cli.simulate import MAX_SIMULATE_POINTS
from roughgp.io import readers, x3p

SHAPES = {"ground": (16, 24), "honed": (16, 24), "turned": (32, 48)}


def _run(capsys, *argv):
    """``main(argv)``: returns (exit code, stdout, stderr)."""
    code = main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return code, out, err


def _simulate(capsys, tmp_path, kind, name, seed=1, shape=None, *extra):
    ny, nx = shape or SHAPES[kind]
    path = tmp_path / name
    code, out, err = _run(capsys, "simulate", kind, "--shape", ny, nx, "--seed", seed,
                          "--out", path, *extra)
    assert code == 0, err
    return path, err


def _read_back(path):
    """The heights of a file written by ``simulate``, read with roughgp.io.readers."""
    if path.suffix == ".npy":
        return np.load(path)
    if path.suffix == ".x3p":
        return x3p.read_x3p(path).z
    return readers.read_surface(path, spacing=1.0)[0]


# ------------------------------------------------------------------ help, version, script

def test_help_mentions_every_command(capsys):
    code, out, _ = _run(capsys, "--help")
    assert code == 0
    for command in ("reproduce", "simulate", "fit", "texture", "check", "fill", "batch", "um"):
        assert command in out
    for argv in (["reproduce"], ["simulate"], ["simulate", "ground"], ["simulate", "honed"],
                 ["simulate", "turned"], ["fit"], ["fit", "profile"], ["fit", "ground"],
                 ["texture"], ["check"], ["fill"], ["batch"]):
        code, out, _ = _run(capsys, *argv, "--help")
        assert code == 0, argv
        assert "example" in out and "roughgp" in out, argv


def test_version(capsys):
    from roughgp import __version__
    code, out, _ = _run(capsys, "--version")
    assert code == 0 and __version__ in out


def test_no_command_is_a_usage_error(capsys):
    code, _, err = _run(capsys)
    assert code == 2 and "reproduce" in err


def test_console_script():
    script = Path(sys.executable).with_name("roughgp")
    assert script.exists(), f"{script} missing: pip install -e . creates it"
    result = subprocess.run([str(script), "--help"], capture_output=True, text=True,
                            timeout=120)
    assert result.returncode == 0, result.stderr
    assert "simulate" in result.stdout and "texture" in result.stdout


# ------------------------------------------------------------------ reproduce

def test_reproduce_list(capsys):
    code, out, _ = _run(capsys, "reproduce", "--list")
    assert code == 0
    for key in ledger.claim_keys():
        assert key in out


def test_reproduce_one_claim_writes_the_ledger(capsys, tmp_path):
    expected = ledger.run(only=["eq5-duality"])[0]
    code, out, err = _run(capsys, "reproduce", "--only", "eq5-duality", "--out", tmp_path)
    assert code == (1 if expected.regressed else 0), err
    assert "eq5-duality" in out and "eq5-duality" in err  # table and progress
    assert all(len(line) <= 100 for line in out.splitlines())
    records = json.loads((tmp_path / "ledger.json").read_text())
    assert [r["key"] for r in records] == ["eq5-duality"]
    markdown = (tmp_path / "ledger.md").read_text()
    assert markdown.startswith("# roughgp claims ledger")
    assert ledger.claim("eq5-duality").where in markdown
    assert (tmp_path / "figures").is_dir() == (records[0]["figure"] is not None)


def test_reproduce_exits_1_and_names_a_regression(capsys, monkeypatch):
    c = ledger.claim("eq5-duality")
    monkeypatch.setattr(ledger, "run", lambda **kw: [ledger.Outcome(c, "way off", False, 0.1)])
    code, out, err = _run(capsys, "reproduce", "--only", "eq5-duality")
    assert code == 1
    assert "REGRESSED" in out and "eq5-duality" in err


def test_reproduce_unknown_key(capsys):
    code, _, err = _run(capsys, "reproduce", "--only", "no-such-claim")
    assert code == 2
    assert "no-such-claim" in err and "eq5-duality" in err
    assert "Traceback" not in err


# ------------------------------------------------------------------ simulate

@pytest.mark.parametrize("kind", ["ground", "honed", "turned"])
def test_simulate_each_kind_and_format(capsys, tmp_path, kind):
    reference = None
    for ext in (".npy", ".csv", ".x3p"):
        path, err = _simulate(capsys, tmp_path, kind, f"{kind}{ext}", 5)
        assert "drawing" in err and "wrote" in err
        z = _read_back(path)
        assert z.shape == SHAPES[kind]
        assert np.all(np.isfinite(z))
        if reference is None:
            reference = z
        else:  # the same seed gives the same surface in every format
            np.testing.assert_allclose(z, reference, rtol=1e-9, atol=1e-9)
    if kind == "ground":
        assert x3p.read_x3p(tmp_path / "ground.x3p").spacing == (1.0, 1.0)


def test_simulate_seeds(capsys, tmp_path):
    a, _ = _simulate(capsys, tmp_path, "ground", "a.npy", 3)
    b, _ = _simulate(capsys, tmp_path, "ground", "b.npy", 3)
    c, _ = _simulate(capsys, tmp_path, "ground", "c.npy", 4)
    assert np.array_equal(np.load(a), np.load(b))
    assert not np.allclose(np.load(a), np.load(c))
    # without --seed a fresh seed is drawn and printed, so the draw can be repeated
    code, _, err = _run(capsys, "simulate", "turned", "--shape", 16, 16, "--out",
                        tmp_path / "d.npy")
    assert code == 0 and "--seed" in err


def test_simulate_options_override_the_preset(capsys, tmp_path):
    _, err = _simulate(capsys, tmp_path, "ground", "g.npy", 1, None, "--angle-deg", 60,
                       "--lambda-a", 50, "--variance", 2, "--noise-variance", 0,
                       "--spacing", 0.5)
    assert "angle 60 deg" in err and "lambda_a 50 um" in err and "variance 2 um^2" in err
    _, err = _simulate(capsys, tmp_path, "honed", "h.npy", 1, None,
                       "--step", 4, 50, 5, 30, "--step", 1, 5, 2, 60)
    assert "2-step honed" in err and "angle 60 deg" in err
    _, err = _simulate(capsys, tmp_path, "turned", "t.x3p", 1, None, "--feed", 20,
                       "--spacing", 0.5)
    assert "feed 20 um" in err
    assert x3p.read_x3p(tmp_path / "t.x3p").spacing == (0.5, 0.5)


def test_simulate_turned_profile(capsys, tmp_path):
    a, _ = _simulate(capsys, tmp_path, "turned", "a.csv", 2, (1, 300))
    code, _, err = _run(capsys, "simulate", "turned", "--profile", 300, "--seed", 2, "--out",
                        tmp_path / "b.npy")
    assert code == 0, err
    x, z = readers.read_profile(a)
    np.testing.assert_allclose(x, np.arange(300.0))
    np.testing.assert_allclose(z, np.load(tmp_path / "b.npy"), rtol=1e-9, atol=1e-9)
    code, _, _ = _run(capsys, "simulate", "turned", "--profile", 300, "--out",
                      tmp_path / "c.x3p")
    assert code == 0 and x3p.read_x3p(tmp_path / "c.x3p").z.shape == (300,)


@pytest.mark.parametrize("shape", [(0, 48), (32, -4), (100000, 100000)])
def test_simulate_refuses_a_bad_shape(capsys, tmp_path, shape):
    code, _, err = _run(capsys, "simulate", "ground", "--shape", *shape, "--out",
                        tmp_path / "z.npy")
    assert code == 2
    assert "--shape" in err and str(MAX_SIMULATE_POINTS) in err
    assert "Traceback" not in err and not (tmp_path / "z.npy").exists()
    if shape[0] == 100000:
        assert "impossible size" in err


def test_simulate_errors(capsys, tmp_path):
    code, _, err = _run(capsys, "simulate", "ground", "--shape", 8, 8, "--out",
                        tmp_path / "z.txt")
    assert code == 2 and ".npy" in err and ".x3p" in err
    code, _, err = _run(capsys, "simulate", "ground", "--out", tmp_path / "z.npy")
    assert code == 2 and "--shape" in err
    # the library's ValueError (a turned surface needs >= 16 points per axis; a bad feed)
    for extra in (["--shape", 8, 8], ["--shape", 16, 16, "--feed", -3]):
        code, _, err = _run(capsys, "simulate", "turned", *extra, "--out", tmp_path / "z.npy")
        assert code == 2 and "error" in err and "Traceback" not in err
    code, _, err = _run(capsys, "simulate", "ground", "--shape", 8, 8, "--spacing", 0,
                        "--out", tmp_path / "z.npy")
    assert code == 2 and "--spacing" in err
    code, _, err = _run(capsys, "simulate", "ground", "--shape", "8", "x", "--out",
                        tmp_path / "z.npy")
    assert code == 2 and "--shape" in err  # argparse's own usage error


# ------------------------------------------------------------------ simulate ground --target

def test_simulate_ground_with_target(capsys, tmp_path):
    from roughgp import targets
    path, err = _simulate(capsys, tmp_path, "ground", "t.npy", 2, (96, 96), "--target",
                          "Sq=1.0", "Sal=4", "Str=0.25", "Std=30", "--noise-variance", 0.05)
    hyper = targets.hyperparameters_for(1.0, 4.0, 0.25, 30.0, noise_variance=0.05)
    assert f"lambda_a {hyper.lengthscales[0]:g} um" in err
    assert f"lambda_b {hyper.lengthscales[1]:g} um" in err and "angle 30 deg" in err
    assert "noise variance 0.05 um^2" in err and "warning" not in err
    achieved = next(line for line in err.splitlines() if line.startswith("achieved"))
    for name in ("Sq", "Sal", "Str", "Std"):
        assert f"{name} " in achieved and "target" in achieved
    z, _ = targets.simulate_with_targets({"Sq": 1.0, "Sal": 4, "Str": 0.25, "Std": 30},
                                            (96, 96), seed=2, noise_variance=0.05)
    np.testing.assert_array_equal(np.load(path), z)
    measured = targets.measure(z)
    assert f"Sq {measured['Sq']:.4g} um (target 1)" in achieved
    assert f"Std {measured['Std']:.4g} deg (target 30)" in achieved


@pytest.mark.parametrize("target, extra, message", [
    (["Sq=1.2", "Sal=40", "Str=0.2"], [], "missing Std"),
    (["Sq=1.2", "Sal=40", "Str=0.2", "Std=30", "Sa=1"], [], "unknown key 'Sa'"),
    (["Sq=1.2", "Sal=40", "Str", "Std=30"], [], "KEY=VALUE"),
    (["Sq=1.2", "Sal=forty", "Str=0.2", "Std=30"], [], "Sal must be a number"),
    (["Sq=1.2", "Sq=1.3", "Sal=40", "Str=0.2", "Std=30"], [], "Sq is given twice"),
    (["Sq=1.0", "Sal=40", "Str=0.2", "Std=30"], [], "Sq must be > sqrt(5 --noise-variance / 4)"),
    (["Sq=1.2", "Sal=40", "Str=0", "Std=30"], [], "Str must be in (0, 1]"),
    (["Sq=1.2", "Sal=-4", "Str=0.2", "Std=30"], [], "Sal must be > 0"),
    (["Sq=2", "Sal=40", "Str=0.2", "Std=30"], ["--lambda-a", "50"], "drop --lambda-a"),
])
def test_simulate_ground_target_errors(capsys, tmp_path, target, extra, message):
    code, _, err = _run(capsys, "simulate", "ground", "--target", *target, *extra, "--shape",
                        32, 32, "--seed", 1, "--out", tmp_path / "z.npy")
    assert code == 2, err
    assert message in err and "--target" in err and "Traceback" not in err
    assert not (tmp_path / "z.npy").exists()


# ------------------------------------------------------------------ fit

def test_fit_turned_profile(capsys, tmp_path):
    path, _ = _simulate(capsys, tmp_path, "turned", "profile.csv", 0, (1, 1024))
    result = tmp_path / "fit.json"
    code, out, err = _run(capsys, "fit", "profile", path, "--mixtures", 2, "--out", result)
    assert code == 0, err
    for word in ("weight", "period", "line width", "noise variance",
                 "log marginal likelihood", "dominant period"):
        assert word in out
    fit = json.loads(result.read_text())
    assert fit["format"] == "roughgp-model" and fit["equation"] == "eq21"
    assert len(fit["hyperparameters"]["weights_um2"]) == 2
    assert fit["data"]["shape"] == [1024] and fit["spacing_um"] == [1.0]
    hp = fit["hyperparameters"]
    peak = np.argmax(np.asarray(hp["weights_um2"]) / np.sqrt(hp["spectral_variances_per_um2"]))
    assert abs(1 / hp["frequencies_per_um"][peak] - 250.0) < 0.02 * 250.0
    assert np.isfinite(fit["fit"]["log_likelihood"])


def test_fit_errors(capsys, tmp_path):
    code, _, err = _run(capsys, "fit", "profile", tmp_path / "missing.csv")
    assert code == 2 and f"no such file: {tmp_path / 'missing.csv'}" in err
    bad = tmp_path / "bad.csv"
    bad.write_text("this is not\na profile at all\n")
    code, _, err = _run(capsys, "fit", "profile", bad)
    assert code == 2 and "bad.csv" in err and "Traceback" not in err
    ragged = tmp_path / "ragged.csv"
    ragged.write_text("0,1\n1,2,3\n")
    code, _, err = _run(capsys, "fit", "profile", ragged)
    assert code == 2 and "line 2" in err
    notnpy = tmp_path / "x.npy"
    notnpy.write_text("garbage")
    code, _, err = _run(capsys, "texture", notnpy)
    assert code == 2 and "not a .npy file" in err
    code, _, err = _run(capsys, "texture", ragged, "--spacing", -1)
    assert code == 2 and "--spacing" in err
    png = tmp_path / "image.png"
    png.write_bytes(b"\x89PNG")
    code, _, err = _run(capsys, "fit", "profile", png)
    assert code == 2 and ".x3p" in err


# ------------------------------------------------------------------ texture

def test_texture_of_surfaces_and_a_profile(capsys, tmp_path):
    npy, _ = _simulate(capsys, tmp_path, "ground", "g.npy", 1)
    x3p, _ = _simulate(capsys, tmp_path, "ground", "g.x3p", 1)
    results = []
    for path in (npy, x3p):
        out_json = tmp_path / f"{path.suffix[1:]}.json"
        code, out, err = _run(capsys, "texture", path, "--unfiltered", "--json", out_json)
        assert code == 0, err
        assert "Sq" in out and "Sal" in out and "Std" in out and "operators: none" in out
        record = json.loads(out_json.read_text(), parse_constant=pytest.fail)
        results.append(record["parameters"]["Sq"])
    np.testing.assert_allclose(results[0], results[1], rtol=1e-9)
    assert results[0] == pytest.approx(np.std(np.load(npy)), rel=1e-9)

    profile, _ = _simulate(capsys, tmp_path, "turned", "p.csv", 1, (1, 600))
    code, out, err = _run(capsys, "texture", profile)
    assert code == 0, err
    assert "Ra" in out and "RSm" in out and "Sq" not in out
    # a 600 um profile is shorter than ISO 4288's cut-off for its Ra: the L-filter is off
    words = " ".join(out.split())  # the notes are wrapped to the terminal
    assert "F: least-squares line" in words and "shorter than lambda_c: L-filter off" in words


def test_texture_flat_surface_prints_nan(capsys, tmp_path):
    flat = tmp_path / "flat.npy"
    np.save(flat, np.zeros((8, 8)))
    code, out, err = _run(capsys, "texture", flat, "--unfiltered", "--json",
                          tmp_path / "flat.json")
    assert code == 0, err
    assert "nan" in out
    record = json.loads((tmp_path / "flat.json").read_text(), parse_constant=pytest.fail)
    assert record["parameters"]["Ssk"] is None and record["parameters"]["Sq"] == 0.0


# ------------------------------------------------------------------ fill


def _holed_surface(tmp_path, name="holes.npy"):
    from roughgp.models import surfaces
    z = surfaces.ground((48, 56), variance=2.0, lengthscales=(10.0, 3.0), angle=0.4,
                        noise_variance=0.05, seed=3) + 0.02 * np.arange(56)[None, :]
    z[np.random.default_rng(4).random(z.shape) < 0.1] = np.nan
    z[20:23, 5:50] = np.nan
    path = tmp_path / name
    np.save(path, z)
    return path, z


def test_fill_writes_the_filled_surface_and_its_sd(capsys, tmp_path):
    path, z = _holed_surface(tmp_path)
    out, sd = tmp_path / "filled.npy", tmp_path / "sd.npy"
    code, _, err = _run(capsys, "fill", path, "--out", out, "--sd", sd, "--block", 12,
                        "--blocks", 6, "--samples", 4, "--seed", 1)
    assert code == 0, err
    assert "eq 18 fitted and self-checked on" in err and "missing (" in err
    filled, spread = np.load(out), np.load(sd)
    missing = np.isnan(z)
    assert filled.shape == z.shape and np.all(np.isfinite(filled))
    np.testing.assert_array_equal(filled[~missing], z[~missing])  # measured points kept
    # the tilt (0.02 per point) is added back: the filled row follows its neighbours
    assert abs(np.mean(filled[21, 5:50]) - np.nanmean(z[[18, 25], 5:50])) < 1.0
    assert np.all(spread[~missing] == 0) and np.all(spread[missing] > 0)


def test_a_band_with_no_hole_size_calibrated_says_so_not_up_to_0_points(capsys, tmp_path):
    """One hole too large for the map to hold out a copy of (a FRT map of 27 % dropouts said
    "calibrated for holes up to 0 points across")."""
    from roughgp.models import surfaces
    z = surfaces.ground((96, 96), variance=1.0, lengthscales=(4.0, 2.0), angle=0.0,
                        noise_variance=0.01, seed=2)
    z[12:84, 12:84] = np.nan
    np.save(tmp_path / "big-hole.npy", z)
    code, _, err = _run(capsys, "fill", tmp_path / "big-hole.npy", "--out", tmp_path / "f.npy",
                        "--band", tmp_path / "b.npy", "--block", 12, "--blocks", 6)
    assert code == 0, err
    assert "band not calibrated by hole size" in err
    assert "no hole size calibrated on this map" in err and "up to 0 points" not in err


def test_a_fill_that_loses_to_linear_interpolation_says_so_with_options_fill_has(
        capsys, tmp_path, monkeypatch):
    """A FRT map with spikes: the self-check's GP erred 8.1 um RMS against linear
    interpolation's 2.9; the command said "the GP worse" and went on without a word of why or
    what to try."""
    import re

    from roughgp.filling.self_check import FillSelfCheck
    monkeypatch.setattr(FillSelfCheck, "verdict", property(lambda self: "linear"))
    path, _ = _holed_surface(tmp_path)
    code, _, err = _run(capsys, "fill", path, "--out", tmp_path / "f.npy", "--block", 12,
                        "--blocks", 6)
    assert code == 0, err
    note = next(line for line in err.splitlines() if line.startswith("note: linear"))
    assert "--spurious" in note and "--nu auto" in note
    _, help_text, _ = _run(capsys, "fill", "--help")
    named = set(re.findall(r"--[a-z-]+", note))
    assert named and all(option in help_text for option in named), named
    code, _, err = _run(capsys, "fill", path, "--out", tmp_path / "g.npy", "--block", 12,
                        "--blocks", 6, "--nu", "auto", "--force")
    note = next(line for line in err.splitlines() if line.startswith("note: linear"))
    assert "--nu auto" not in note   # what was given is not suggested again


def test_fill_checks_itself_chooses_nu_and_writes_the_calibrated_band(capsys, tmp_path):
    path, z = _holed_surface(tmp_path)
    out, band = tmp_path / "filled.npy", tmp_path / "band.npy"
    code, _, err = _run(capsys, "fill", path, "--out", out, "--band", band, "--nu", "auto",
                        "--block", 12, "--blocks", 6, "--seed", 1)
    assert code == 0, err
    checks = [line for line in err.splitlines() if line.startswith("self-check: ")
              and "measured points held out and filled" in line]
    assert len(checks) == 3 and sum("<- used" in line for line in checks) == 1
    half = np.load(band)
    missing = np.isnan(z)
    assert np.all(half[~missing] == 0) and np.all(half[missing] > 0)
    assert "self-check: the band calibrated by hole size and depth" in err
    assert ("predictive sd, by size of hole and depth and the roughness around the hole, "
            "calibrated for holes up to") in err
    # --no-check: no self-check, the Gaussian band
    code, _, err = _run(capsys, "fill", path, "--out", tmp_path / "plain.npy", "--band",
                        tmp_path / "plain-band.npy", "--no-check", "--block", 12, "--blocks", 6)
    assert code == 0, err
    assert "self-check: " not in err and "1.96 predictive sd (Gaussian, no self-check)" in err


@pytest.mark.parametrize("extra, message", [
    (("--nu", "auto", "--no-check"), "--nu auto chooses by the self-check"),
    (("--nu", "0.7"), "invalid choice: '0.7'"),
    (("--method", "global", "--samples", "1", "--sd", "SD"), "--samples must be in [2, 256]"),
    (("--samples", "-1"), "--samples must be in [2, 256]"),
    (("--samples", "100000"), "--samples must be in [2, 256]"),
    (("--device", "gpu"), "--device must be None"),
    (("--block", "3"), "--block must be in [4, 32]"),
    (("--block", "64"), "--block must be in [4, 32]"),
    (("--seed", "-1"), "--seed must be in [0, 4294967295], got -1"),
    (("--spacing", "1e-300"), "--spacing must be in [1e-06, 1e+06] um"),
    (("--blocks", "100000"), "--blocks must be in [1, 200]"),
])
def test_fill_rejects_bad_options(capsys, tmp_path, extra, message):
    path, _ = _holed_surface(tmp_path)
    extra = [str(tmp_path / "sd.npy") if e == "SD" else e for e in extra]
    code, _, err = _run(capsys, "fill", path, "--out", tmp_path / "f.npy", *extra)
    assert code == 2 and message in err


def test_fill_needs_a_surface_with_holes(capsys, tmp_path):
    complete = tmp_path / "complete.npy"
    np.save(complete, np.zeros((16, 16)))
    code, _, err = _run(capsys, "fill", complete, "--out", tmp_path / "f.npy")
    assert code == 2 and "no missing (NaN) point: nothing to fill" in err
    profile = tmp_path / "profile.npy"
    np.save(profile, np.r_[np.zeros(10), np.nan])
    code, _, err = _run(capsys, "fill", profile, "--out", tmp_path / "f.npy")
    assert code == 2 and "holds a profile" in err
