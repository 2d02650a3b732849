"""roughgp.experiments.long_correlation: eq 18 in 2-D against AR fits and FFT filters (small
sizes and a stand-in for figure 2's draw; the ledger runs the paper's)."""

import math
import types

import numpy as np
import pytest

from roughgp.experiments import long_correlation as lc
from roughgp.models import surfaces

SMALL = surfaces.GrooveParameters(variance=2.0, lengthscales=(40.0, 2.0), angle=math.pi / 6)
DRAWN = types.SimpleNamespace(torus_shape=(8, 8), min_eigenvalue=0.1, clipped_fraction=0.0)


@pytest.fixture(scope="module")
def result():
    return lc.long_correlation_2d(parameters=SMALL, orders=(1, 2, 4), window=60, fft_size=512,
                                  short_lambda_a=4.0, grid=256, max_along=100.0,
                                  ground_surface=DRAWN)


def test_fits_errors_and_curves_have_their_shapes(result):
    assert set(result.fits) == {(k, p) for k in ("quarter", "half") for p in (1, 2, 4)}
    assert set(result.short_fits) == {("half", p) for p in (1, 2, 4)}
    n = result.along_lags.size
    assert result.true_along.shape == result.filter_along.shape == (n,)
    assert all(f.along.shape == (n,) and f.max_error > 0 for f in result.fits.values())
    assert result.true_along[0] == 1.0
    assert result.best("half").max_error == min(result.fits["half", p].max_error
                                               for p in (1, 2, 4))
    assert result.torus_shape == (8, 8) and result.clipped_fraction == 0.0


def test_short_fits_converge_and_the_filter_wraps_little_across(result):
    short = [result.short_fits["half", p].max_error for p in (1, 2, 4)]
    assert short[-1] < short[0]
    # the grid-size filter's ACVF is eq 18 periodised: at lag 0 it lacks the PSD beyond Nyquist
    assert result.filter_along[0] < 1.0
    assert result.filter_wrap_error == pytest.approx(
        float(np.abs(result.filter_along - result.true_along).max()))


def test_windows_beyond_the_torus_are_refused():
    with pytest.raises(ValueError, match="within half"):
        lc.long_correlation_2d(parameters=SMALL, window=300, fft_size=512, grid=256,
                               ground_surface=DRAWN)
