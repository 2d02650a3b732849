"""One bounds table for the options (issue 32, "unbounded inside the documented ranges" and
the unclear messages): each bounded option is refused out of its range before any work,
with its name and range; --help states the same range; --unit, --unfiltered and a profile
given to a surface model are refused or read right, never ignored."""

from __future__ import annotations

import os
import time
from pathlib import Path

import numpy as np
import pytest

from roughgp.cli.bounds import BOUNDS, bounds_text
from roughgp.cli.main import main
from roughgp.cli.parser import build_parser
from roughgp.io import x3p
from cli_run import run as _run

DATA = Path(__file__).resolve().parents[2] / "data"
LAND = DATA / "sample-land.x3p"


@pytest.fixture
def surface(tmp_path):
    path = tmp_path / "s.x3p"
    z = np.random.default_rng(0).normal(size=(24, 30))
    z[3, 4] = np.nan
    x3p.write_x3p(path, z, 1.0)
    return path


@pytest.fixture
def no_reading(monkeypatch):
    """Fail if the input is read: the option's check comes before any work."""
    from roughgp.io import measurement

    def refuse(*args, **kwargs):
        raise AssertionError("the input was read before the option was checked")
    monkeypatch.setattr(measurement, "read_measurement", refuse)


@pytest.mark.parametrize("argv, option, allowed", [
    (["fill", "S", "--out", "f.npy", "--seed", "-1"], "--seed", "[0, 4294967295]"),
    (["fit", "ground", "S", "--seed", "-1"], "--seed", "[0, 4294967295]"),
    (["check", "M", "S", "--seed", "-1"], "--seed", "[0, 4294967295]"),
    (["simulate", "ground", "--shape", "8", "8", "--seed", "-1", "--out", "g.npy"], "--seed",
     "[0, 4294967295]"),
    (["texture", "S", "--spacing", "1e-300"], "--spacing", "[1e-06, 1e+06] um"),
    (["texture", "S", "--spacing", "1e300"], "--spacing", "[1e-06, 1e+06] um"),
    (["fit", "profile", "S", "--spacing", "1e300"], "--spacing", "[1e-06, 1e+06] um"),
    (["simulate", "ground", "--shape", "8", "8", "--spacing", "1e-300", "--out", "g.npy"],
     "--spacing", "[1e-06, 1e+06] um"),
    (["texture", "S", "--l-filter", "1e300"], "--l-filter", "[1e-06, 1e+06] um"),
    (["texture", "S", "--s-filter", "1e-300"], "--s-filter", "[1e-06, 1e+06] um"),
    (["fit", "ground", "S", "--block", "64"], "--block", "[4, 32]"),
    (["fill", "S", "--out", "f.npy", "--block", "64"], "--block", "[4, 32]"),
    (["check", "M", "S", "--simulations", "999"], "--simulations", "[2, 99]"),
    (["fit", "profile", "S", "--mixtures", "100000000"], "--mixtures", "[1, 50]"),
    (["texture", "S", "--form", "polynomial", "--degree", "1000000000"], "--degree", "[1, 10]"),
    (["texture", "S", "--channel", "-1"], "--channel", "[0, 255]"),
])
def test_an_option_out_of_its_range_is_refused_before_any_work(capsys, tmp_path, surface,
                                                               no_reading, argv, option,
                                                               allowed):
    swap = {"S": str(surface), "M": str(tmp_path / "m.json")}
    argv = [swap.get(a, a) for a in argv]
    argv = [str(tmp_path / a) if a.endswith(".npy") else a for a in argv]
    start = time.perf_counter()
    code, _, err = _run(capsys, *argv)
    assert code == 2 and f"error: {option} must be in {allowed}, got " in err, err
    assert len(err.strip().splitlines()) == 1 and "Traceback" not in err
    assert time.perf_counter() - start < 5.0


def test_the_largest_value_of_each_range_is_accepted(capsys, surface):
    """Calibration: the ends of the ranges pass (the command then fails on the map, not on
    the option)."""
    code, _, err = _run(capsys, "texture", surface, "--spacing", "1e6", "--l-filter", "1e6",
                        "--form", "polynomial", "--degree", "10", "--channel", "255")
    assert "must be in" not in err, err


def _parsers():
    parser = build_parser()
    stack, found = [("roughgp", parser)], []
    while stack:
        name, current = stack.pop()
        found.append((name, current))
        for action in current._actions:
            if hasattr(action, "choices") and isinstance(action.choices, dict):
                stack += [(f"{name} {k}", p) for k, p in action.choices.items()]
    return found


def test_every_help_states_the_range_of_the_table():
    seen = set()
    for name, parser in _parsers():
        for action in parser._actions:
            for option in set(action.option_strings) & set(BOUNDS):
                seen.add(option)
                assert bounds_text(option) in (action.help or ""), (name, option, action.help)
    assert seen == set(BOUNDS)  # every bound is some command's option


def test_l_filter_longer_than_the_field_is_refused(capsys, surface):
    code, _, err = _run(capsys, "texture", surface, "--l-filter", "1000")
    assert code == 2 and "--l-filter 1000 um exceeds the field (30 um" in err, err
    code, _, err = _run(capsys, "texture", surface, "--l-filter", "25", "--s-filter", "none")
    assert code == 0, err


def _sq(text):
    return float(next(line.split()[1] for line in text.splitlines() if line.split()[:1] == ["Sq"]))


@pytest.mark.parametrize("name", ["z.npy", "z.csv"])
def test_unit_is_applied_to_heights_files_and_an_implausible_result_refused(capsys, tmp_path,
                                                                           name):
    z = np.random.default_rng(1).normal(size=(20, 24))
    path = tmp_path / name
    if name.endswith(".npy"):
        np.save(path, z)
    else:
        np.savetxt(path, z, delimiter=",")
    code, out, err = _run(capsys, "texture", path, "--unfiltered")
    assert code == 0, err
    code, out_mm, err = _run(capsys, "texture", path, "--unfiltered", "--unit", "mm")
    assert code == 0, err
    assert _sq(out_mm) == pytest.approx(1000 * _sq(out), rel=1e-6)
    code, _, err = _run(capsys, "texture", path, "--unit", "m")   # heights of metres: refused
    assert code == 2 and "implausible" in err, err


def test_unit_is_refused_for_an_x3p(capsys, tmp_path):
    path = tmp_path / "z.x3p"
    x3p.write_x3p(path, np.random.default_rng(1).normal(size=(20, 24)), 1.0)
    code, _, err = _run(capsys, "texture", path, "--unit", "mm")
    assert code == 2 and "x3p" in err and "unit" in err, err
    assert _run(capsys, "texture", path)[0] == 0


def test_unit_is_applied_to_an_instrument_file(capsys):
    code, out, err = _run(capsys, "texture", DATA / "opd-1.opd", "--unfiltered")
    assert code == 0, err
    code, out_nm, err = _run(capsys, "texture", DATA / "opd-1.opd", "--unfiltered", "--unit",
                             "um")
    assert code == 0, err

    def sq(text):
        return float(next(line.split()[1] for line in text.splitlines()
                          if line.split()[:1] == ["Sq"]))
    # the file states mm; --unit um reads its numbers as um: 1000 times smaller heights
    assert sq(out) == pytest.approx(1000 * sq(out_nm), rel=1e-6)


@pytest.mark.parametrize("extra", [["--l-filter", "8"], ["--form", "cylinder"],
                                   ["--form", "plane"], ["--s-filter", "none"]])
def test_unfiltered_refuses_the_operator_options(capsys, surface, extra):
    code, _, err = _run(capsys, "texture", surface, "--unfiltered", *extra)
    assert code == 2 and f"--unfiltered applies no operator: drop {extra[0]}" in err, err


def test_unfiltered_alone_runs(capsys, surface):
    code, out, err = _run(capsys, "texture", surface, "--unfiltered")
    assert code == 0 and "none (unfiltered)" in out, err


def test_a_profile_is_not_checked_as_a_surface(capsys, tmp_path, surface):
    model = tmp_path / "m.json"
    assert main(["fit", "ground", str(surface), "--block", "8", "--blocks", "2",
                 "--out", str(model)]) == 0
    profile = tmp_path / "profile.csv"
    x = np.arange(512) * 0.5
    np.savetxt(profile, np.column_stack((x, np.sin(x))), delimiter=",")
    capsys.readouterr()
    code, _, err = _run(capsys, "check", model, profile, "--simulations", 3)
    assert code == 2 and "holds a profile (512 points)" in err and "surface model" in err, err


def test_simulate_from_errors_name_the_command_not_none(capsys, tmp_path):
    code, _, err = _run(capsys, "simulate", "--from", tmp_path / "none.json", "--shape", 4, 4,
                        "--out", tmp_path / "x.npy")
    assert code == 2 and err.startswith("roughgp simulate: error: --from: no such model file")
    assert "None" not in err


def test_a_symlink_loop_as_model_file_is_a_clear_error(capsys, tmp_path):
    one, two = tmp_path / "one.json", tmp_path / "two.json"
    os.symlink(two, one)
    os.symlink(one, two)
    code, _, err = _run(capsys, "simulate", "--from", one, "--shape", 4, 4,
                        "--out", tmp_path / "x.npy")
    assert code == 2 and "Traceback" not in err and len(err.strip().splitlines()) == 1
    assert f"--from: cannot read the model file {one}" in err, err


def test_fill_help_names_nanofocus_for_nms(capsys):
    assert main(["fill", "--help"]) == 0
    out = capsys.readouterr().out
    assert "NanoFocus .nms" in out and "Nanosurf" not in out


@pytest.fixture(scope="module")
def profile_model(tmp_path_factory):
    """A two-column profile (x at 0.5 um) and a profile model fitted to it."""
    folder = tmp_path_factory.mktemp("profile-model")
    x = np.arange(512) * 0.5
    z = np.sin(x) + 0.3 * np.random.default_rng(0).standard_normal(512)
    profile = folder / "profile.csv"
    np.savetxt(profile, np.column_stack((x, z)), delimiter=",")
    model = folder / "pm.json"
    assert main(["fit", "profile", str(profile), "--mixtures", "2", "--seed", "0",
                 "--out", str(model)]) == 0
    return model, profile, z


def test_a_profile_model_checks_a_two_column_profile_as_a_profile(capsys, profile_model):
    model, profile, _ = profile_model
    capsys.readouterr()
    code, out, err = _run(capsys, "check", model, profile, "--simulations", 3)
    assert code == 0, err
    assert "simulating 3 profiles of 512 points" in err  # not a 512 x 2 surface
    assert "Rq" in out and "Sq" not in out and "spacing" not in out  # 0.5 um, as fitted


def test_a_profile_model_refuses_a_surface(capsys, profile_model, tmp_path):
    model, _, _ = profile_model
    surface = tmp_path / "s.npy"
    np.save(surface, np.random.default_rng(1).standard_normal((32, 32)))
    code, _, err = _run(capsys, "check", model, surface, "--simulations", 3)
    assert code == 2 and "holds a surface (32 x 32 points)" in err and "profile model" in err


def test_a_profile_without_its_spacing_is_checked_with_a_note_saying_so(capsys, profile_model,
                                                                         tmp_path):
    model, _, z = profile_model
    one_column = tmp_path / "heights.csv"
    np.savetxt(one_column, z)  # no x column: the spacing is assumed 1 um
    code, out, err = _run(capsys, "check", model, one_column, "--simulations", 3)
    assert code == 0, err
    text = " ".join(out.split())  # the note is wrapped
    assert "note: the file's spacing 1 um (assumed" in text and "model's 0.5 um" in text
    code, out, _ = _run(capsys, "check", model, one_column, "--simulations", 3,
                        "--spacing", 0.5)
    assert code == 0 and "note: the file's spacing" not in out
