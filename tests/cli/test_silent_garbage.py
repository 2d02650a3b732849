"""Inputs that used to give non-finite or meaningless numbers with exit 0 (issue 18, "Silent
garbage"): absurd scales for ``simulate``, heights of 1e200, a complex ``.npy``."""

from __future__ import annotations

import numpy as np
import pytest

from roughgp.io.measurement import read_measurement
from roughgp.io.readers import MalformedFileError
from roughgp.metrology.texture import areal_parameters, profile_parameters
from cli_run import run as _run


@pytest.mark.parametrize("option, value", [
    ("--noise-variance", "1e300"), ("--spacing", "1e300"), ("--variance", "1e308"),
    ("--lambda-b", "1e-300"), ("--lambda-a", "inf"), ("--noise-variance", "-1"),
    ("--spacing", "nan")])
def test_simulate_refuses_absurd_scales_naming_the_option(capsys, tmp_path, option, value):
    out = tmp_path / "z.npy"
    code, _, err = _run(capsys, "simulate", "ground", "--shape", "16", "16", "--seed", "1",
                        option, value, "--out", out)
    assert code == 2, err
    assert f"error: {option} must be" in err
    assert "allowed range" in err or f"{option} must be in [" in err  # the range stated
    assert "Traceback" not in err and not out.exists()


def test_simulate_turned_and_honed_options_are_checked_too(capsys, tmp_path):
    code, _, err = _run(capsys, "simulate", "turned", "--profile", "64", "--feed", "1e300",
                        "--out", tmp_path / "p.csv")
    assert code == 2 and "--feed must be" in err
    code, _, err = _run(capsys, "simulate", "honed", "--shape", "16", "16", "--step", "1e308",
                        "5", "3", "45", "--out", tmp_path / "h.npy")
    assert code == 2 and "--step VARIANCE must be" in err


def test_simulate_at_the_edge_of_the_range_writes_finite_heights(capsys, tmp_path):
    out = tmp_path / "z.npy"
    code, _, err = _run(capsys, "simulate", "ground", "--shape", "16", "16", "--seed", "1",
                        "--lambda-b", "1e-60", "--out", out)
    assert code == 0, err
    assert np.all(np.isfinite(np.load(out)))


def test_non_finite_drawn_heights_are_an_error_and_nothing_is_written(capsys, tmp_path,
                                                                      monkeypatch):
    from roughgp.models import surfaces
    monkeypatch.setattr(surfaces, "ground", lambda shape, **kw: np.full(shape, np.inf))
    out = tmp_path / "z.npy"
    code, _, err = _run(capsys, "simulate", "ground", "--shape", "8", "8", "--seed", "1",
                        "--out", out)
    assert code == 2 and "not all finite" in err and "--spacing" in err
    assert not out.exists()


def test_profile_parameters_of_huge_heights_scale_with_them():
    z = np.random.default_rng(0).normal(size=256)
    small, big = profile_parameters(z), profile_parameters(z * 1e200)
    for name in ("Ra", "Rq", "Rp", "Rv", "Rt", "Rk", "Rpk", "Rvk"):
        assert big[name] == pytest.approx(small[name] * 1e200, rel=1e-12), name
    for name in ("Rsk", "Rku", "RSm", "Mr1", "Mr2"):
        assert big[name] == pytest.approx(small[name], rel=1e-9, abs=1e-12), name


def test_areal_parameters_of_huge_heights_scale_with_them():
    z = np.random.default_rng(1).normal(size=(32, 32))
    with np.errstate(over="raise", invalid="raise"):
        small, big = areal_parameters(z), areal_parameters(z * 1e200)
    for name in ("Sq", "Sa", "Sz"):
        assert big[name] == pytest.approx(small[name] * 1e200, rel=1e-12), name
    for name in ("Ssk", "Sku", "Sal", "Str", "Std"):
        assert big[name] == pytest.approx(small[name], rel=1e-9), name


def test_a_complex_npy_is_refused_not_truncated(capsys, tmp_path):
    path = tmp_path / "c.npy"
    np.save(path, np.ones((8, 8)) + 1j)
    with pytest.raises(MalformedFileError, match=r"c\.npy: holds complex128 values, not real "
                                                 r"heights.*z\.real"):
        read_measurement(path)
    code, _, err = _run(capsys, "texture", path)
    assert code == 2 and "complex" in err and "ComplexWarning" not in err
