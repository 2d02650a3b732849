"""fit_spectral_mixture refuses work it cannot finish before computing (issue 32, "unbounded
inside the documented ranges"): Q = 1e8, n_candidates = 1e7, 10^6 points, each refused with
the parameter and its range, at once."""

from __future__ import annotations

import time

import numpy as np
import pytest

from roughgp.inference import fitting


@pytest.mark.parametrize("points, kwargs, words", [
    (256, {"num_mixtures": 10**8}, "num_mixtures must be an integer >= 1 and <= 100"),
    (256, {"num_mixtures": 2, "n_candidates": 10**7},
     "n_candidates must be an integer >= 1 and <= 1000"),
    (10**6, {"num_mixtures": 2}, "allowed range: [16, 65536] points"),
])
def test_work_beyond_the_bounds_is_refused_at_once(points, kwargs, words):
    x = np.arange(points, dtype=float)
    z = np.sin(0.3 * x)
    start = time.perf_counter()
    with pytest.raises(ValueError) as excinfo:
        fitting.fit_spectral_mixture(x, z, seed=0, **kwargs)
    assert words in str(excinfo.value)
    assert time.perf_counter() - start < 5.0


def test_the_largest_allowed_settings_are_accepted_by_the_checks(monkeypatch):
    """Calibration: the bounds themselves pass the checks (the fit is stopped right after)."""
    class Stop(Exception):
        pass

    def stop(*args, **kwargs):
        raise Stop
    monkeypatch.setattr(fitting, "as_generator", stop)
    x = np.arange(fitting.MAX_POINTS, dtype=float)
    with pytest.raises(Stop):
        fitting.fit_spectral_mixture(x, np.sin(0.3 * x), fitting.MAX_MIXTURES,
                                     n_candidates=fitting.MAX_CANDIDATES, seed=0)


@pytest.mark.parametrize("factor", [1e-300, 1e300])
def test_positions_scaled_beyond_float64_are_refused_by_name(factor):
    """Issue 44 part 2: positions scaled by 1e-300 returned infinite variances with only a
    RuntimeWarning."""
    x = np.arange(256, dtype=float) * factor
    with pytest.raises(ValueError, match=r"the spacing of x must be > 0 and within \[1e-60"):
        fitting.fit_spectral_mixture(x, np.sin(0.3 * np.arange(256.0)), 1, seed=0)
