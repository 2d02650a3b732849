"""Issue 44 part 2, data loss and late writes: every output of a command (--out, --sd, --band,
--flagged, --json, --plot) is checked against every input (FILE, MODEL, --model) and against
every other output in one place (roughgp.cli.output.check_outputs), before any work; the map of
--flagged is written with the other outputs, after every check, so a refusal leaves no file."""

from __future__ import annotations

import numpy as np
import pytest

from cli_run import run as _run


@pytest.fixture
def small(tmp_path):
    """A small map with a few holes."""
    z = np.random.default_rng(0).normal(size=(16, 20))
    z[3, 4] = z[7, 9] = np.nan
    path = tmp_path / "small.npy"
    np.save(path, z)
    return path


def _same_bytes(path, before):
    return path.read_bytes() == before


@pytest.mark.parametrize("name", ["mm.npy", "mm.csv"])
def test_fill_flagged_over_the_model_input_is_refused(capsys, tmp_path, small, name):
    model = tmp_path / name
    model.write_text("not touched\n")
    before = model.read_bytes()
    code, _, err = _run(capsys, "fill", small, "--model", model, "--out", tmp_path / "fo.npy",
                        "--force", "--spurious", "--flagged", model)
    assert code == 2, err
    assert "--flagged" in err and "(--model)" in err and "is the input file" in err
    assert _same_bytes(model, before)
    assert not (tmp_path / "fo.npy").exists()


def test_check_flagged_over_the_model_input_is_refused(capsys, tmp_path, small):
    model = tmp_path / "MODEL.csv"
    model.write_text("not touched\n")
    before = model.read_bytes()
    code, _, err = _run(capsys, "check", model, small, "--spurious", "--flagged", model,
                        "--force")
    assert code == 2 and "--flagged" in err and "(MODEL)" in err, err
    assert _same_bytes(model, before)


def test_fit_flagged_over_the_file_is_refused(capsys, tmp_path, small):
    before = small.read_bytes()
    code, _, err = _run(capsys, "fit", "ground", small, "--out", tmp_path / "m.json",
                        "--spurious", "--flagged", small, "--force")
    assert code == 2 and "--flagged" in err and "(FILE)" in err, err
    assert _same_bytes(small, before) and not (tmp_path / "m.json").exists()


def test_fill_flagged_and_out_naming_one_file_is_refused(capsys, tmp_path, small):
    out = tmp_path / "fo2.npy"
    code, _, err = _run(capsys, "fill", small, "--out", out, "--spurious", "--flagged", out)
    assert code == 2 and "--flagged and --out name the same file" in err, err
    assert not out.exists()


def test_fill_flagged_and_sd_naming_one_file_is_refused(capsys, tmp_path, small):
    sd = tmp_path / "s3.npy"
    code, _, err = _run(capsys, "fill", small, "--out", tmp_path / "o3.npy", "--sd", sd,
                        "--spurious", "--flagged", sd)
    assert code == 2 and "--flagged and --sd name the same file" in err, err
    assert not sd.exists() and not (tmp_path / "o3.npy").exists()


def test_flagged_without_spurious_is_refused_before_any_work(capsys, tmp_path, small):
    code, _, err = _run(capsys, "fill", small, "--out", tmp_path / "o.npy", "--flagged",
                        tmp_path / "f.npy")
    assert code == 2 and "give --spurious too" in err
    assert list(tmp_path.iterdir()) == [small]


def test_fill_without_holes_writes_no_flagged_map(capsys, tmp_path):
    """``fill`` of a complete map with --spurious --flagged wrote fl.npy, then said "nothing to
    fill"."""
    path = tmp_path / "complete.npy"
    np.save(path, np.random.default_rng(1).normal(size=(32, 32)))
    flagged = tmp_path / "fl.npy"
    code, _, err = _run(capsys, "fill", path, "--out", tmp_path / "o.npy", "--spurious",
                        "--flagged", flagged)
    assert code == 2 and "nothing to fill" in err, err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["complete.npy"]
