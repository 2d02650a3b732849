"""The feed marks of a periodic profile (roughgp.metrology.feed_marks): found where a turned
profile has them, refused where a stationary random profile has none (the calibration of
REPRODUCIBLE), bad input refused by name."""

from __future__ import annotations

import numpy as np
import pytest

from roughgp.metrology.feed_marks import REPRODUCIBLE, NoPeriodError, feed_marks
from roughgp.models import turned
from roughgp.surface_models.periodic_draw import ar1


def _ar1(n, length, rng):
    """A stationary profile of exponential ACVF (eq 18 in one dimension), correlation length
    ``length`` samples (an AR(1) sequence)."""
    return ar1(n, 1.0, np.exp(-1.0 / length), rng)


@pytest.mark.parametrize("seed", range(4))
def test_a_turned_profile_gives_its_feed_and_mark(seed):
    _, z = turned.turned_profile(2048, 1.0, seed=seed)
    marks = feed_marks(z, 1.0)
    assert abs(marks.feed / turned.RUBERT_LIKE.feed - 1) < 0.01
    assert marks.reproducibility > 0.9 and marks.explained > 0.99
    # the mark's height is the kinematic peak-to-valley height, within the edge's roughness
    assert abs(marks.height - turned.RUBERT_LIKE.rt) < 1.0
    # the trace follows the profile to within its random parts
    residual = z - z.mean() - marks.profile(np.arange(z.size) * 1.0)
    assert residual.std() < 0.3


@pytest.mark.parametrize("length", [2, 20, 200])
def test_stationary_profiles_hold_no_mark(length):
    """The calibration: 25 stationary profiles per correlation length (up to a tenth of the
    profile), none passes; the largest share explained out of sample stays far below the
    threshold (it was 0.05 over 200 such profiles when REPRODUCIBLE was set)."""
    rng = np.random.default_rng(length)
    for _ in range(25):
        with pytest.raises(NoPeriodError, match="no feed mark"):
            feed_marks(_ar1(2048, length, rng), 1.0)


def test_a_mark_survives_holes_and_noise():
    _, z = turned.turned_profile(2048, 1.0, seed=5)
    z = z + np.random.default_rng(0).normal(0, 0.5, z.size)
    z[300:420] = np.nan
    marks = feed_marks(z, 1.0)
    assert abs(marks.feed / 250 - 1) < 0.01 and marks.reproducibility > REPRODUCIBLE


def test_without_shifts_and_depths_the_trace_is_the_mark_repeated():
    """... but at the cusps, where the copies' continued flanks cut each other."""
    _, z = turned.turned_profile(2048, 1.0, seed=1)
    marks = feed_marks(z, 1.0)
    x = np.arange(2048) * 1.0
    zero = np.zeros(marks.shifts.size)
    trace, repeated = marks.profile(x, zero, zero), marks.mark_at(x - marks.origin)
    phase = np.mod(x - marks.origin, marks.feed) / marks.feed
    away = (phase > 1 / 32 + 0.01) & (phase < 1 - 1 / 32 - 0.01)
    np.testing.assert_allclose(trace[away], repeated[away], atol=1e-12)
    assert np.all(trace <= repeated + 1e-12)


@pytest.mark.parametrize("feed, words", [(2.0, "= [4, 512] um"),
                                         (600.0, "= [4, 512] um"),
                                         (-1.0, "feed")])
def test_a_given_feed_out_of_range_is_refused(feed, words):
    _, z = turned.turned_profile(2048, 1.0, seed=1)
    with pytest.raises(ValueError) as error:
        feed_marks(z, 1.0, feed=feed)
    assert words in str(error.value)


def test_a_given_feed_is_kept():
    _, z = turned.turned_profile(2048, 1.0, seed=1)
    assert feed_marks(z, 1.0, feed=250.0).feed == 250.0


@pytest.mark.parametrize("profile, error, words", [
    (np.zeros(64), NoPeriodError, "constant"),
    (np.arange(10.0), NoPeriodError, "too short"),
    (np.full(100, np.nan), ValueError, "at least half measured"),
    (np.zeros((4, 64)), ValueError, "1-D"),
])
def test_what_holds_no_mark_is_refused(profile, error, words):
    with pytest.raises(error, match=words):
        feed_marks(profile, 1.0)


def test_a_fold_too_coarse_to_sharpen_is_kept_without_a_degenerate_fit():
    """A FRT map with no feed marks: the search tried marks of 8 to 15 samples, and sharpening
    fitted a quadratic through the 2 samples of a flank (numpy's RankWarning reached the user
    as "warning: Polyfit may be poorly conditioned")."""
    import warnings

    from roughgp.metrology.feed_marks import _sharpened
    for n in range(4, 17):   # 16 too: round(16 / 32) is 0, and its flank held 2 samples
        mark = np.cos(np.linspace(0, 2 * np.pi, n, endpoint=False))
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            np.testing.assert_array_equal(_sharpened(mark), mark)
    cusp = np.abs(np.linspace(-1, 1, 64))   # fine enough: the ends continued from the flanks
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert _sharpened(cusp).shape == cusp.shape
