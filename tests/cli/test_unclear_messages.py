"""Issue 44 part 2, "unclear messages": each names the option or field and says what to change,
and suggests no option the command does not have."""

from __future__ import annotations

import argparse
import math

import numpy as np

from roughgp.cli.output import shell_message
from roughgp.sampling.truncation import too_large_error
from cli_run import run as _run


def test_a_correlation_too_long_for_any_torus_names_the_options():
    """``simulate ground --shape 4096 4096 --lambda-a 5000`` said "most negative nan x r(0) ...
    tried []" (40 s to reach; the message is built here as the sampler builds it)."""
    error = too_large_error((4096, 4096), (1.0, 1.0), math.nan, math.nan, 1e-10, None, [],
                            (18816, 177408), 134217728)
    args = argparse.Namespace(method="auto", kind="ground")
    message = shell_message(str(error), args)
    assert "nan" not in message and "tried []" not in message
    assert "no torus could be tried" in message and "(18816, 177408)" in message
    assert "--lambda-a" in message and "--shape" in message and "approximate=" not in message


def test_a_one_row_map_read_as_a_surface_is_told_the_options_of_texture(capsys, tmp_path):
    """It suggested ``order=0``, a library argument the command does not have."""
    path = tmp_path / "row.npy"
    np.save(path, np.random.default_rng(0).normal(size=(1, 64)))
    code, _, err = _run(capsys, "texture", path, "--kind", "surface")
    assert code == 2 and "order=0" not in err, err
    assert "--form none" in err and "--kind profile" in err


def _mostly_holes(tmp_path):
    z = np.random.default_rng(0).normal(size=(48, 48))
    z[:, 1::3] = z[:, 2::3] = np.nan
    path = tmp_path / "holes.npy"
    np.save(path, z)
    return path


def test_spurious_on_a_map_of_many_holes_names_no_block_option(capsys, tmp_path):
    """texture --spurious said "use a smaller block or a lower min_valid": texture takes
    neither."""
    code, _, err = _run(capsys, "texture", _mostly_holes(tmp_path), "--spurious")
    assert code == 2 and "min_valid" not in err and "--block" not in err, err
    assert "--spurious" in err and "crop the map" in err


def test_fill_on_a_map_of_many_holes_names_its_block_option(capsys, tmp_path):
    code, _, err = _run(capsys, "fill", _mostly_holes(tmp_path), "--out", tmp_path / "o.npy")
    assert code == 2 and "min_valid" not in err and "give a smaller --block" in err, err


def test_a_johnson_marginal_refused_is_quoted_as_the_file_states_it(capsys, tmp_path):
    """It quoted the latent skewness 4.24 and kurtosis 7, which the file does not hold."""
    from roughgp.surface_models.model import FittedModel
    model = FittedModel("eq18", {"variance_um2": 1.0, "lambda_a_um": 4.0, "lambda_b_um": 2.0,
                                 "angle_deg": 0.0, "noise_variance_um2": 1.0}, (1.0, 1.0),
                        marginal={"skewness": 1.5, "kurtosis": 4.0})
    path = model.save(tmp_path / "m.json")
    code, _, err = _run(capsys, "simulate", "--from", path, "--shape", 16, 16, "--seed", 0,
                        "--out", tmp_path / "o.npy")
    assert code == 2, err
    assert "skewness 1.5 and kurtosis 4 cannot be drawn" in err
    assert "give a marginal kurtosis above 7" in err and "noise_variance_um2" in err
    assert not (tmp_path / "o.npy").exists()


def test_a_5000_digit_seed_is_refused_with_the_options_range(capsys, tmp_path):
    """It gave Python's message of its int() limit (and echoed the 5000 digits)."""
    code, _, err = _run(capsys, "simulate", "ground", "--shape", 8, 8, "--lambda-a", 4,
                        "--seed", "9" * 5000, "--out", tmp_path / "s.npy")
    assert code == 2 and "--seed" in err and "in [0, 4294967295]" in err, err
    assert "9" * 100 not in err and "limit" not in err
    code, _, err = _run(capsys, "fill", tmp_path / "x.npy", "--out", tmp_path / "o.npy",
                        "--block", "x")
    assert code == 2 and "argument --block: expected an integer, got 'x'" in err, err


def test_a_name_too_long_for_the_temporary_file_is_refused_before_the_fit(capsys, tmp_path,
                                                                         monkeypatch):
    """A 246-character output name failed only after the fit, on its temporary name."""
    from roughgp.surface_models import fit as surface_fit

    def never(*args, **kwargs):
        raise AssertionError("fitted before checking the output's name")
    monkeypatch.setattr(surface_fit, "fit_surface_model", never)
    path = tmp_path / "z.npy"
    np.save(path, np.random.default_rng(0).normal(size=(16, 16)))
    out = tmp_path / ("a" * 241 + ".json")
    code, _, err = _run(capsys, "fit", "ground", path, "--out", out)
    assert code == 2 and "--out: the file name is 246 bytes long" in err, err
    assert "at most 232 bytes" in err


def test_a_file_name_that_is_not_utf8_goes_into_the_x3p_comment(capsys, tmp_path):
    """A non-UTF-8 input name failed only after the fill, on the x3p comment."""
    import os

    import roughgp
    z = np.random.default_rng(0).normal(size=(16, 16))
    z[3, 3] = np.nan
    path = os.path.join(os.fsdecode(bytes(tmp_path)), os.fsdecode(b"\xffbad.npy"))
    np.save(path, z)
    out = tmp_path / "f.x3p"
    code, _, err = _run(capsys, "fill", path, "--out", out, "--no-check", "--block", 8)
    assert code == 0, err
    assert "\\xffbad.npy" in roughgp.read(out).meta["comment"]


def test_texture_of_a_map_of_coarse_steps_chooses_no_s_filter(capsys, tmp_path):
    """``texture testing.x3p`` (x3ptools' test file) stopped with "min() arg is an empty
    sequence": 3 spacings beyond the largest preferred nesting index left no S-filter to
    choose."""
    path = tmp_path / "coarse.npy"
    np.save(path, np.random.default_rng(0).normal(size=(20, 20)))
    code, out, err = _run(capsys, "texture", path, "--spacing", 30000)
    assert code == 0, err
    assert "no S-filter: 3 spacings (90 mm)" in " ".join(out.split())
    assert "Sq" in out
