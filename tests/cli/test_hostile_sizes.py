"""Sizes that used to end in a traceback (issue 18, "Tracebacks"): a huge text table, a huge
map for ``texture``, an overflowing ``--target``, library calls whose arrays would not fit in
memory, a kernel function returning the wrong shape. Each is refused before it allocates,
with a ValueError (exit code 2 on the command line) that names the parameter and the limit."""

from __future__ import annotations

import math

import numpy as np
import pytest

from roughgp.io import readers, x3p
from roughgp.io.readers import MalformedFileError
from roughgp.metrology import texture_report
from cli_run import run as _run


def _exponential(lags):
    return np.exp(-np.sqrt(np.sum(np.asarray(lags) ** 2, axis=-1)))


# --------------------------------------------------------------------------- text tables

def test_a_text_table_over_the_byte_limit_is_refused_before_parsing(tmp_path, monkeypatch):
    path = tmp_path / "big.csv"
    np.savetxt(path, np.random.default_rng(0).normal(size=(200, 2)), delimiter=",")
    monkeypatch.setattr(readers, "MAX_TEXT_BYTES", 1024)
    parsed = []
    monkeypatch.setattr(readers, "_token", lambda t: parsed.append(t) or 0.0)
    with pytest.raises(MalformedFileError, match=r"big\.csv: the file is .* MiB.*MAX_TEXT_BYTES"):
        readers.read_profile(path)
    assert parsed == []                                    # refused before one value is read


def test_a_text_table_over_the_point_limit_stops_while_parsing(tmp_path, monkeypatch):
    path = tmp_path / "many.txt"
    np.savetxt(path, np.zeros((50, 4)))
    monkeypatch.setattr(readers, "MAX_POINTS", 64)
    with pytest.raises(MalformedFileError, match=r"many\.txt: line 17: more than MAX_POINTS"):
        readers.read_surface(path, spacing=1.0)


def test_the_cli_reports_a_huge_text_file_with_exit_2(capsys, tmp_path, monkeypatch):
    path = tmp_path / "big.csv"
    np.savetxt(path, np.zeros((100, 2)), delimiter=",")
    monkeypatch.setattr(readers, "MAX_TEXT_BYTES", 100)
    code, _, err = _run(capsys, "texture", path)
    assert code == 2 and "MAX_TEXT_BYTES" in err and "Traceback" not in err


# --------------------------------------------------------------------------- texture

def test_texture_refuses_a_map_over_its_point_limit(capsys, tmp_path, monkeypatch):
    path = tmp_path / "big.x3p"
    x3p.write_x3p(path, np.zeros((64, 64)), 1.0)
    monkeypatch.setattr(texture_report, "MAX_TEXTURE_POINTS", 1000)
    code, _, err = _run(capsys, "texture", path)
    assert code == 2, err
    assert "64 x 64 = 4096 points" in err and "MAX_TEXTURE_POINTS = 1000" in err
    assert "GiB" in err and "Traceback" not in err


def test_texture_refuses_a_map_that_would_not_fit_in_free_memory(monkeypatch):
    monkeypatch.setattr(texture_report, "host_free_bytes", lambda: 10**6)
    with pytest.raises(ValueError, match=r"need about .* GiB, but only .* GiB of memory"):
        texture_report.filtered_parameters(np.zeros((64, 64)))


def test_the_texture_limit_matches_a_4096_square_map():
    texture_report.check_texture_size((4096, 4096))  # allowed by the point limit...
    with pytest.raises(ValueError, match="16384 x 16384 = 268435456 points.*MAX_TEXTURE_POINTS"):
        texture_report.check_texture_size((16384, 16384))


# --------------------------------------------------------------------------- simulate --target

def test_an_overflowing_target_is_a_clear_error(capsys, tmp_path):
    code, _, err = _run(capsys, "simulate", "ground", "--target", "Sq=1e300", "Sal=40",
                        "Str=0.2", "Std=30", "--shape", "32", "32", "--out", tmp_path / "o.npy")
    assert code == 2, err
    assert "Sq" in err and "allowed range" in err and "Traceback" not in err
    assert not (tmp_path / "o.npy").exists()


# --------------------------------------------------------------------------- library sizes

def test_sample_grid_refuses_a_grid_beyond_memory():
    from roughgp.sampling import sample_grid
    with pytest.raises(ValueError, match=r"shape = \(1000000, 1000000\).*GiB.*allowed"):
        sample_grid(_exponential, (10**6, 10**6))


def test_sample_grid_refuses_too_many_samples():
    from roughgp.sampling import sample_grid
    with pytest.raises(ValueError, match=r"n_samples = 1000000000.*GiB.*allowed"):
        sample_grid(_exponential, (8, 8), n_samples=10**9)


def test_fill_gaps_refuses_too_many_draws():
    from roughgp.filling.global_fill import fill_gaps
    from roughgp.gp.kernels import RotatedExponentialKernel
    z = np.random.default_rng(0).normal(size=(16, 16))
    z[3, 3] = np.nan
    with pytest.raises(ValueError, match=r"n_samples = 10000000 pathwise draws.*GiB"):
        fill_gaps(z, RotatedExponentialKernel(1.0, (3.0, 2.0), 0.0), noise_variance=0.1,
                  n_samples=10**7)


def test_sample_posterior_refuses_a_chain_beyond_memory():
    from roughgp.inference.posterior import (
        LogUniform,
        Parameter,
        PosteriorModel,
        profile_likelihood,
        sample_posterior,
    )
    z = np.random.default_rng(1).normal(size=20)
    model = PosteriorModel((Parameter("variance", LogUniform(1e-4, 1e4)),),
                           profile_likelihood(z, 1.0, lambda p, lags: p["variance"] * (lags == 0)))
    with pytest.raises(ValueError, match=r"n_steps = 1000000000 steps.*GiB"):
        sample_posterior(model, n_walkers=4, n_steps=10**9, seed=0)


def test_simulate_arma_refuses_a_profile_beyond_memory():
    from roughgp.models.arma import simulate_arma
    with pytest.raises(ValueError, match=r"n = 10000000000 points.*GiB"):
        simulate_arma([0.5], [], 1.0, 10**10)


@pytest.mark.parametrize("method", ["cholesky", "circulant", "auto"])
def test_a_kernel_function_of_the_wrong_shape_is_a_clear_error(method):
    from roughgp.sampling import sample_grid
    with pytest.raises(ValueError, match=r"kernel must return one covariance per lag"):
        sample_grid(lambda lags: np.ones(3), (8, 8), method=method)


def test_a_correct_kernel_function_still_draws():
    from roughgp.sampling import sample_grid
    z = sample_grid(_exponential, (8, 8), seed=0)
    assert z.shape == (1, 8, 8) and np.all(np.isfinite(z)) and math.isfinite(z.std())


@pytest.mark.parametrize("error, words", [(OverflowError("(34, 'Result too large')"),
                                            "overflowed"), (MemoryError(), "out of memory")])
def test_overflow_and_memory_errors_exit_2_without_a_traceback(capsys, tmp_path, monkeypatch,
                                                                error, words):
    from roughgp.metrology import texture_report

    def fail(*args, **kwargs):
        raise error
    path = tmp_path / "t.x3p"
    x3p.write_x3p(path, np.zeros((8, 8)), 1.0)
    monkeypatch.setattr(texture_report, "filtered_parameters", fail)
    code, _, err = _run(capsys, "texture", path)
    assert code == 2 and words in err and "Traceback" not in err
