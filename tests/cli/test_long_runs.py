"""Issue 44 part 2, unbounded runs: ``check`` (plain or ``--calibrate``) says, after its first
simulation or bootstrap copy, how long the whole run will take at that pace when it is long,
naming the options that shorten it (roughgp.cli.pace); ``--spurious`` after its first round,
``simulate --from`` after a pilot draw."""

from __future__ import annotations

import numpy as np
import pytest

from roughgp.cli import pace
from roughgp.surface_models.model import FittedModel
from cli_run import run as _run


@pytest.fixture
def model_and_map(tmp_path):
    model = FittedModel("eq18", {"variance_um2": 1.0, "lambda_a_um": 3.0, "lambda_b_um": 1.5,
                                 "angle_deg": 0.0, "noise_variance_um2": 0.01}, (1.0, 1.0),
                        stage="form-removed", cutoffs={"form": "plane", "s_um": None,
                                                       "l_um": None},
                        fit={"seed": 0, "block": 8, "n_blocks": 4})
    z = model.simulate((16, 16), seed=1)
    np.save(tmp_path / "z.npy", z)
    return model.save(tmp_path / "m.json"), tmp_path / "z.npy"


@pytest.mark.parametrize("options, words", [
    (("--simulations", 3), "warning: 3 simulations (each drawn and measured) take about"),
    (("--simulations", 2, "--calibrate", 2),
     "warning: 2 bootstrap copies, each refitted and checked take about"),
])
def test_a_long_check_is_announced_with_its_estimate(capsys, monkeypatch, model_and_map,
                                                     options, words):
    monkeypatch.setattr(pace, "LONG_RUN_S", -1.0)  # every run is long
    model, z = model_and_map
    code, _, err = _run(capsys, "check", model, z, *options, "--seed", 0)
    assert code == 0, err
    assert words in err and "--simulations" in err and "--part" in err
    assert err.count("warning: ") == 1


def test_a_short_check_says_nothing_of_its_length(capsys, model_and_map):
    model, z = model_and_map
    code, _, err = _run(capsys, "check", model, z, "--simulations", 3, "--seed", 0)
    assert code == 0 and "take about" not in err, err


def test_durations_in_words():
    assert [pace.duration(s) for s in (45, 200, 7200)] == ["45 s", "3.3 min", "2.0 h"]


def test_a_long_spurious_detection_is_announced_without_an_option_it_lacks(capsys, monkeypatch,
                                                                          tmp_path):
    """``texture --spurious`` (a 1024² map took minutes) says after its first round how long
    its rounds may take, and names no option texture does not have."""
    from roughgp.models import surfaces
    monkeypatch.setattr(pace, "LONG_RUN_S", -1.0)
    z = surfaces.ground((48, 48), variance=1.0, lengthscales=(4.0, 2.0), angle=0.0,
                        noise_variance=0.01, seed=2)
    z[10, 10] += 8.0
    np.save(tmp_path / "spiky.npy", z)
    code, _, err = _run(capsys, "texture", tmp_path / "spiky.npy", "--spurious")
    assert code == 0, err
    assert "--spurious rounds (at most; each fits the map and scores every point) take " \
        "about" in err and "a smaller map or crop would make it shorter" in err
    assert err.count("take about") == 1


def test_a_long_draw_from_a_model_is_announced_after_a_pilot(capsys, monkeypatch, model_and_map,
                                                              tmp_path):
    """``simulate --from`` at 2048² took two minutes unannounced: a large draw is timed on a
    pilot a sixteenth of its size first, and announced when long."""
    monkeypatch.setattr(pace, "LONG_RUN_S", -1.0)
    monkeypatch.setattr(pace, "PILOT_FROM_POINTS", 64 * 64)
    model, _ = model_and_map
    code, _, err = _run(capsys, "simulate", "--from", model, "--shape", 64, 64, "--out",
                        tmp_path / "big.npy", "--seed", 1)
    assert code == 0, err
    assert "warning: this draw takes about" in err and "16 x 16 points" in err
    assert "a smaller --shape makes it shorter" in err
    monkeypatch.setattr(pace, "LONG_RUN_S", 60.0)
    code, _, err = _run(capsys, "simulate", "--from", model, "--shape", 64, 64, "--out",
                        tmp_path / "big2.npy", "--seed", 1)
    assert code == 0 and "takes about" not in err, err


def test_a_long_fill_is_announced_after_its_first_window_and_suggests_no_option(
        capsys, monkeypatch, model_and_map, tmp_path):
    """``fill`` of a map that is mostly holes (a 512² Digital Surf map, 89 % missing, took
    three minutes) says how long its windows take at the pace of the first; no option of fill
    shortens them, so none is named."""
    monkeypatch.setattr(pace, "LONG_RUN_S", -1.0)
    model, z = model_and_map
    holed = np.load(z)
    holed[:10] = np.nan
    np.save(tmp_path / "holed.npy", holed)
    code, _, err = _run(capsys, "fill", tmp_path / "holed.npy", "--model", model,
                        "--out", tmp_path / "f.npy")
    assert code == 0, err
    assert "windows of the fill take about" in err and "(Ctrl-C stops it)" in err
    assert err.count("warning: ") == 1 and "--" not in err.split("take about")[1].split("\n")[0]


def test_the_pace_is_timed_from_the_start_of_the_units_not_from_what_came_before(
        capsys, monkeypatch):
    """``fill`` makes its Pace before the fit and the self-check; their seconds are not the
    windows' pace (a 96² fill of 0.3 s was announced as 1.8 min)."""
    clock = iter([0.0, 100.0, 100.5])   # created; the units start at 100; the first ends
    monkeypatch.setattr(pace.time, "perf_counter", lambda: next(clock))
    tell = pace.Pace("windows", None)
    tell(0, 36)
    tell(1, 36)
    assert tell.estimate == pytest.approx(18.0)
    assert "take about" not in capsys.readouterr().err
