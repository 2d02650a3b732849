"""Errors a shell user can act on (issue 18, "Messages"): they name the command's options, not
the library's parameters or keyword arguments; no numpy reprs; tiny maps, holes and closed
pipes get plain words; ``.x3p`` output is reproducible byte for byte."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from roughgp.cli.output import rename_parameters, shell_message
from roughgp.io import x3p
from cli_run import run as _run

ROOT = Path(__file__).resolve().parents[2]


@pytest.mark.parametrize("argv, says, not_says", [
    (["--profile", "2"], "--profile must be an integer >= 16", "error: n must"),
    (["--shape", "1", "10"], "NX of --shape 1 NX must be", "error: n must"),
    (["--shape", "2", "2"], "--shape must be (ny, nx) with both >= 16", "error: shape"),
    (["--profile", "64", "--feed", "1"], "--feed must be > 4 x the feed-mark jitter",
     "feed_jitter"),
    (["--profile", "64", "--nose-radius", "1"], "--nose-radius must be > --feed / 2 = 125",
     "nose_radius")])
def test_simulate_turned_errors_name_the_options(capsys, tmp_path, argv, says, not_says):
    code, _, err = _run(capsys, "simulate", "turned", *argv, "--out", tmp_path / "t.csv")
    assert code == 2, err
    assert says in err and not_says not in err


def test_numpy_reprs_become_plain_numbers():
    assert shell_message("got np.float64(1.5) and np.int64(3), np.True_") == "got 1.5 and 3, True"


def test_library_advice_is_rewritten_for_the_shell(capsys, tmp_path, monkeypatch):
    from roughgp.models import surfaces
    from roughgp.sampling.circulant import NotEmbeddableError

    def refuse(*args, **kwargs):
        raise NotEmbeddableError("circulant embedding keeps negative eigenvalues. Use "
                                 "approximate=True to clip (the lost variance is reported), a "
                                 "smaller grid, or method='cholesky'.")
    monkeypatch.setattr(surfaces, "ground", refuse)
    code, _, err = _run(capsys, "simulate", "ground", "--shape", "8", "8", "--seed", "1",
                        "--out", tmp_path / "g.npy")
    assert code == 2
    assert "approximate=True" not in err and "method='cholesky'" not in err
    assert "--method cholesky" in err and "--shape" in err


def test_the_library_still_advises_what_the_cli_rewrites():
    # the embedding's refusal (both truncations raise this one) as the library words it, and
    # as a shell user reads it
    from roughgp.sampling import truncation

    error = truncation.too_large_error((100, 100), (1.0, 1.0), -0.5, 0.01, 1e-10, (512, 512),
                                       [(256, 256), (512, 512)], (1024, 1024), 2**18)
    assert "approximate=True" in str(error) and "method='cholesky'" in str(error)
    shell = shell_message(str(error))
    assert "approximate=True" not in shell and "method='cholesky'" not in shell
    assert "Give a smaller --shape" in shell


def test_rename_parameters_replaces_whole_words_only():
    names = {"n": "--profile", "feed": "--feed"}
    assert rename_parameters("n must be >= 16 (ny, nx), feed_jitter < feed / 4", names) == \
        "--profile must be >= 16 (ny, nx), feed_jitter < --feed / 4"


@pytest.fixture
def tiny(tmp_path):
    z = np.random.default_rng(0).normal(size=(3, 10))
    z[1, 2] = np.nan
    path = tmp_path / "tiny.x3p"
    x3p.write_x3p(path, z, 1.0)
    return path


@pytest.mark.parametrize("command", [["fill"], ["fit", "ground"]])
def test_a_map_too_small_for_the_block_fit_says_so(capsys, tiny, tmp_path, command):
    code, _, err = _run(capsys, *command, tiny, "--out", tmp_path / "o.json"
                        if command[0] == "fit" else tmp_path / "o.npy")
    assert code == 2
    assert "tiny.x3p is 3 x 10 points" in err and "at least 4 points along each axis" in err
    assert "[4, 3]" not in err


def test_a_default_block_larger_than_the_map_names_the_option(capsys, tmp_path):
    z = np.random.default_rng(0).normal(size=(12, 16))
    z[3, 3] = np.nan
    path = tmp_path / "small.x3p"
    x3p.write_x3p(path, z, 1.0)
    code, _, err = _run(capsys, "fill", path, "--out", tmp_path / "o.npy")
    assert code == 2 and "--block 24 exceeds the shorter side" in err and "--block 4 to 12" in err


def test_a_profile_with_holes_names_the_file_and_what_to_do(capsys, tmp_path):
    x = np.arange(64) * 0.5
    z = np.sin(x)
    z[5] = np.nan
    path = tmp_path / "holes.csv"
    np.savetxt(path, np.column_stack((x, z)), delimiter=",", fmt="%.6f")
    code, _, err = _run(capsys, "fit", "profile", path)
    assert code == 2 and "holes.csv" in err and "1 of 64 points unmeasured" in err
    assert "crop" in err


def test_a_surface_with_an_empty_column_points_to_fill(capsys, tmp_path):
    z = np.random.default_rng(0).normal(size=(16, 64))
    z[:, 7] = np.nan
    path = tmp_path / "column.x3p"
    x3p.write_x3p(path, z, 1.0)
    code, _, err = _run(capsys, "fit", "profile", path)
    assert code == 2 and "column.x3p" in err and "roughgp fill" in err


def test_a_closed_pipe_ends_quietly(tmp_path):
    path = tmp_path / "t.x3p"
    x3p.write_x3p(path, np.random.default_rng(0).normal(size=(16, 16)), 1.0)
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    proc = subprocess.Popen([sys.executable, "-m", "roughgp.cli.main", "texture", str(path)],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, env=env, cwd=ROOT)
    proc.stdout.close()  # the reader has gone before the command prints
    err = proc.stderr.read().decode()
    code = proc.wait(timeout=120)
    assert code == 141, err
    assert "Broken pipe" not in err and "Traceback" not in err and "Exception" not in err


def test_same_seed_and_source_date_epoch_give_byte_identical_x3p(capsys, tmp_path,
                                                                   monkeypatch):
    monkeypatch.setenv("SOURCE_DATE_EPOCH", "1700000000")
    files = []
    for name in ("a.x3p", "b.x3p"):
        code, _, err = _run(capsys, "simulate", "ground", "--shape", "16", "16", "--seed", "4",
                            "--out", tmp_path / name)
        assert code == 0, err
        files.append((tmp_path / name).read_bytes())
    assert files[0] == files[1]
    assert x3p.read_x3p(tmp_path / "a.x3p").meta["date"].timestamp() == 1700000000


def test_a_bad_source_date_epoch_is_a_clear_error(monkeypatch):
    monkeypatch.setenv("SOURCE_DATE_EPOCH", "-5")
    with pytest.raises(ValueError, match="SOURCE_DATE_EPOCH must be whole seconds"):
        x3p.creation_date()


def test_target_and_step_errors_name_the_options(capsys, tmp_path):
    code, _, err = _run(capsys, "simulate", "ground", "--shape", "8", "8", "--target", "Sq=1",
                        "Sal=4", "Str=0.2", "Std=30", "--out", tmp_path / "g.npy")
    assert code == 2 and "--noise-variance = 1" in err and "noise_variance" not in err
    code, _, err = _run(capsys, "simulate", "honed", "--shape", "8", "8", "--step", "1", "5",
                        "3", "nan", "--out", tmp_path / "h.npy")
    assert code == 2 and "--step ANGLE_DEG must be a finite angle" in err


def test_an_option_the_command_does_not_take_is_named_by_that_command(capsys, tmp_path):
    """Not roughgp's top-level usage: the command, the arguments, and for check why the
    operator options are not its own."""
    code, _, err = _run(capsys, "check", tmp_path / "m.json", tmp_path / "m.npy",
                        "--l-filter", 5)
    assert code == 2
    assert err.startswith("roughgp check: error: unrecognized arguments: --l-filter 5")
    assert "stated in MODEL.json" in err and "usage: roughgp [-h]" not in err
    code, _, err = _run(capsys, "texture", tmp_path / "m.npy", "--bogus")
    assert code == 2 and "roughgp texture: error: unrecognized arguments: --bogus" in err
    assert "MODEL.json" not in err
