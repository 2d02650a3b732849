"""``--spurious`` / ``--flagged`` of roughgp fill, fit ground, check and texture: what is removed
is said, the map written, nothing removed unless asked, misuse refused with exit 2."""

from __future__ import annotations

import numpy as np
import pytest

from roughgp.experiments.spurious_points import draw_surface
from cli_run import run as _run


@pytest.fixture(scope="module")
def spiked(tmp_path_factory):
    """A 48 x 64 eq 18 map with 3 spikes / pits and a hole, as .npy."""
    z = draw_surface("eq 18", (48, 64), 11)
    z[10, 20] += 40.0
    z[30, 40] -= 40.0
    z[40, 10] += 30.0
    z[20:23, 50:53] = np.nan
    path = tmp_path_factory.mktemp("spurious") / "spiked.npy"
    np.save(path, z)
    return path, z


def test_fill_spurious_writes_the_mask_and_fills_the_flagged_points(capsys, tmp_path, spiked):
    path, z = spiked
    out, mask = tmp_path / "filled.npy", tmp_path / "flagged.npy"
    code, _, err = _run(capsys, "fill", path, "--spurious", "--flagged", mask, "--out", out)
    assert code == 0, err
    flagged = np.load(mask).astype(bool)
    assert flagged[10, 20] and flagged[30, 40] and flagged[40, 10]
    assert flagged.sum() <= 6
    assert "--spurious:" in err and "flagged spurious" in err
    assert "not flagged spurious" in err  # the self-check says what it scores
    filled = np.load(out)
    assert np.all(np.isfinite(filled))
    assert abs(filled[10, 20] - z[10, 20]) > 20  # the spike replaced by the fill
    unflagged = ~flagged & np.isfinite(z)
    assert np.array_equal(filled[unflagged], z[unflagged])


def test_texture_without_spurious_removes_nothing(capsys, spiked):
    path, _ = spiked
    code, out, err = _run(capsys, "texture", path, "--spacing", 1)
    assert code == 0 and "--spurious" not in err


@pytest.mark.parametrize("argv, message", [
    (("texture", "{path}", "--flagged", "m.npy"), "give --spurious too"),
    (("texture", "{profile}", "--spurious"), "holds a profile"),
    (("texture", "{path}", "--spurious", "--flagged", "{path}"), "--flagged"),
])
def test_misuse_exits_2_with_one_line(capsys, tmp_path, spiked, argv, message):
    path, z = spiked
    profile = tmp_path / "profile.csv"
    np.savetxt(profile, np.column_stack([np.arange(64.0), z[0]]), delimiter=",")
    argv = [a.format(path=path, profile=profile) for a in argv]
    code, _, err = _run(capsys, *argv)
    assert code == 2 and message in err
    assert "Traceback" not in err


def test_a_part_s_fit_and_the_held_out_check_leave_out_the_whole_file_s_points(capsys, tmp_path,
                                                                                spiked):
    """``--part left --spurious``: the points are found on the whole file, so the map of flagged
    points is the file's (the pit in the right half flagged too), and ``fit ground --part`` and
    ``check --held-out`` leave out the same points (the detection on the left half alone
    flagged other points near its cut, and the check's map differed from the fit's)."""
    path, z = spiked
    model, fitted, checked = tmp_path / "m.json", tmp_path / "fit.npy", tmp_path / "check.npy"
    code, _, err = _run(capsys, "fit", "ground", path, "--part", "left", "--spurious",
                        "--flagged", fitted, "--block", "12", "--blocks", "4", "--l-filter",
                        "none", "--out", model)
    assert code == 0, err
    flagged = np.load(fitted).astype(bool)
    assert flagged.shape == z.shape
    assert flagged[10, 20] and flagged[30, 40] and flagged[40, 10]
    code, _, err = _run(capsys, "check", model, path, "--held-out", "--spurious", "--flagged",
                        checked, "--simulations", "4")
    assert code == 0, err
    assert np.array_equal(np.load(checked).astype(bool), flagged)
