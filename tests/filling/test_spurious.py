"""Spurious points: the GP's leave-one-out scores, the robust detector, the metrologists'
methods, calibrated on surfaces whose spurious points are known."""

import math

import numpy as np
import pytest
import scipy.linalg

from roughgp.experiments.spurious_points import GROUND, draw_surface, inject
from roughgp.filling.local_fill import lag_table
from roughgp.filling.spurious import (
    THRESHOLD,
    describe_flagged,
    detect_spurious,
    flag_by,
    flag_k_sq,
    flag_median,
    flag_robust_filter,
    loo_scores,
    noise_floor,
)
from roughgp.sampling.grid_sampler import acvf_of

NOISE = 0.1


def _clean(shape=(64, 64), seed=1):
    return draw_surface("eq 18", shape, seed)


def test_threshold_is_the_stated_false_alarm_rate():
    assert THRESHOLD == pytest.approx(3.8906, abs=1e-4)  # two-sided normal, 1e-4


def test_loo_scores_equal_brute_force_leave_one_out():
    """With one window over the whole grid the scores are the exact LOO residuals over the
    LOO predictive sd: each point removed in turn and kriged from all the others."""
    z = _clean((12, 10), seed=2)
    z[3, 4] = np.nan
    kernel = GROUND.kernel()
    scores = loo_scores(z, kernel, noise_variance=NOISE, tile=16, margin=16)
    table = lag_table(acvf_of(kernel), z.shape, (1.0, 1.0))
    iy, ix = np.nonzero(np.isfinite(z))
    values = z[iy, ix] - np.mean(z[iy, ix])
    cov = table[iy[:, None] - iy[None, :] + 11, ix[:, None] - ix[None, :] + 9]
    cov = cov + NOISE * np.eye(iy.size)
    for i in (0, 17, 60, iy.size - 1):
        keep = np.arange(iy.size) != i
        c = scipy.linalg.cho_factor(cov[np.ix_(keep, keep)])
        k = cov[keep, i]
        mean = k @ scipy.linalg.cho_solve(c, values[keep])
        var = cov[i, i] - k @ scipy.linalg.cho_solve(c, k)
        assert scores[iy[i], ix[i]] == pytest.approx((values[i] - mean) / math.sqrt(var),
                                                     rel=1e-8)
    assert np.isnan(scores[3, 4])


def test_scores_are_standard_normal_under_the_true_model():
    """The calibration a threshold's false-alarm rate rests on: on draws of the model with its
    own hyperparameters the windowed scores have sd 1 and few beyond the threshold."""
    z = _clean((96, 96), seed=3)
    scores = loo_scores(z, GROUND.kernel(), noise_variance=NOISE)
    assert np.nanstd(scores) == pytest.approx(1.0, abs=0.03)
    assert np.mean(np.abs(scores) > THRESHOLD) < 5e-4
    # a wrong (10x) noise variance is not calibrated: the check can say no
    wrong = loo_scores(z, GROUND.kernel(), noise_variance=10 * NOISE + 2.0)
    assert abs(np.nanstd(wrong) - 1.0) > 0.1


def test_excluded_points_are_scored_from_the_others():
    z = _clean((48, 48), seed=4)
    z[20, 20] += 30.0
    excluded = np.zeros(z.shape, bool)
    excluded[20, 20] = True
    scores = loo_scores(z, GROUND.kernel(), noise_variance=NOISE, excluded=excluded)
    assert scores[20, 20] > 10
    # its neighbours no longer see the spike
    assert np.all(np.abs(scores[19:22, 19:22][~excluded[19:22, 19:22]]) < THRESHOLD)


def test_an_isolated_speck_is_scored_against_the_prior():
    """A measured point alone in its window (a speck in a region the instrument could not
    measure: ``data/frt-2.frt`` has 153 at one floor height, 70 um below its surface) is scored
    against the prior, not left unjudged; a speck at its true height is not flagged."""
    truth = _clean((64, 64), seed=8)
    z = truth.copy()
    z[:30] = np.nan
    z[5, 5] = truth[5, 5] + 40.0
    z[5, 40] = truth[5, 40]
    kernel = GROUND.kernel()
    scores = loo_scores(z, kernel, noise_variance=NOISE)
    prior = lag_table(acvf_of(kernel), z.shape, (1.0, 1.0))[63, 63] + NOISE
    offset = np.nanmean(z)
    for at in ((5, 5), (5, 40)):
        assert scores[at] == pytest.approx((z[at] - offset) / math.sqrt(prior), rel=1e-12)
    excluded = np.zeros(z.shape, bool)
    excluded[5, 5] = True  # a speck left out of the fit: still scored, from nothing
    kept = np.isfinite(z) & ~excluded
    assert loo_scores(z, kernel, noise_variance=NOISE, excluded=excluded)[5, 5] == (
        pytest.approx((z[5, 5] - z[kept].mean()) / math.sqrt(prior), rel=1e-12))
    found = detect_spurious(z, seed=0, form=None)  # no plane extrapolated 25 rows out
    assert found.flagged[5, 5] and not found.flagged[5, 40]
    assert f"of {np.isfinite(z).sum()} measured" in found.summary()  # the specks count


def test_detector_finds_injected_points_and_robust_rounds_matter():
    case = inject(_clean((64, 64), seed=5), 0.01, seed=6)
    robust = detect_spurious(case.z, seed=0)
    one = detect_spurious(case.z, seed=0, rounds=1)
    n = case.truth.sum()
    found = (robust.flagged & case.truth).sum() / n
    assert found >= 0.95
    assert (robust.flagged & ~case.truth).sum() / (~case.truth).sum() < 1e-3
    assert (one.flagged & case.truth).sum() / n < found  # the first fit hides the small ones
    assert robust.noise_variance < 0.5 * one.noise_variance
    assert np.array_equal(robust.first_flagged, one.flagged)  # its first round is one pass


def test_detector_flags_almost_nothing_on_a_clean_surface():
    z = _clean((64, 64), seed=7)
    first = detect_spurious(z, seed=0)
    assert first.flagged.mean() < 1e-3
    again = detect_spurious(z, seed=0)  # the same seed, the same scores
    assert np.array_equal(again.scores, first.scores, equal_nan=True)


def test_noise_floor_bounds_the_white_noise_from_above_and_ignores_spikes():
    """On a smooth surface plus white noise of sd 0.5 the floor is near 0.25; on eq 18 (noise
    0.1) it is above the noise (the surface's own curvature adds to it); 1 % spikes of 20 sd
    move it by little; and a surface with no noise gives a floor near 0, not 0.25."""
    rng = np.random.default_rng(0)
    y, x = np.mgrid[0:96, 0:96]
    smooth = np.sin(x / 15.0) + 0.5 * np.cos(y / 20.0)
    noisy = smooth + 0.5 * rng.normal(size=smooth.shape)
    assert noise_floor(noisy) == pytest.approx(0.25, rel=0.1)
    assert noise_floor(smooth) < 1e-3
    assert noise_floor(_clean((96, 96), seed=9)) > NOISE
    spiked = inject(noisy, 0.01, seed=1).z
    assert noise_floor(spiked) == pytest.approx(noise_floor(noisy), rel=0.1)
    holes = noisy.copy()
    holes[::3, ::3] = np.nan
    assert noise_floor(holes) == pytest.approx(0.25, rel=0.15)
    assert noise_floor(np.full((2, 2), np.nan)) == 0.0


def test_floor_keeps_a_collapsed_noise_fit_from_flagging_the_noise():
    """A smooth surface plus white noise, scored with a noise variance collapsed to 1e-12 (as
    the fit does on data/sur-2.sur): the scores flag a large share; with the floor in its place,
    hardly any."""
    rng = np.random.default_rng(2)
    z = _clean((48, 48), seed=10) + 0.7 * rng.normal(size=(48, 48))
    collapsed = loo_scores(z, GROUND.kernel(), noise_variance=1e-12)
    floored = loo_scores(z, GROUND.kernel(), noise_variance=noise_floor(z))
    assert np.mean(np.abs(collapsed) > THRESHOLD) > 0.01
    assert np.mean(np.abs(floored) > THRESHOLD) < 1e-3


def test_metrologists_methods_on_a_known_case():
    z = _clean((64, 64), seed=8)
    spiked = z.copy()
    spiked[30, 30] += 20 * z.std()
    spiked[10, 50] -= 20 * z.std()
    spiked[5, 5] = np.nan
    for flags in (flag_k_sq(spiked), flag_median(spiked), flag_robust_filter(spiked)):
        assert flags[30, 30] and flags[10, 50] and not flags[5, 5]
    # k Sq cannot find a 3-sd spike that sits in a valley; the median residual can
    mild = z.copy()
    low = np.unravel_index(np.argmin(z), z.shape)
    mild[low] += 3 * z.std()
    assert not flag_k_sq(mild)[low]


def test_describe_flagged_says_how_many_and_where():
    flagged = np.zeros((10, 10), bool)
    flagged[2, 3] = flagged[7, 7] = flagged[7, 8] = True
    text = describe_flagged(flagged, np.ones((10, 10), bool))
    assert text.startswith("3 of 100 measured points flagged") and "(7, 8) x2" in text
    assert "(2, 3)" in text
    assert describe_flagged(np.zeros((3, 3), bool), np.ones((3, 3), bool)).startswith("no point")


@pytest.mark.parametrize("call, name", [
    (lambda: detect_spurious(np.zeros((20, 20)), threshold=0), "threshold"),
    (lambda: detect_spurious(np.zeros((20, 20)), rounds=0), "rounds"),
    (lambda: detect_spurious(np.zeros(20)), "z"),
    (lambda: detect_spurious(np.zeros((20, 20)), floor="yes"), "floor"),
    (lambda: flag_by("mad", np.zeros((20, 20))), "method"),
    (lambda: loo_scores(np.full((5, 5), np.nan), GROUND.kernel(), noise_variance=0.1), "fewer"),
])
def test_bad_input_names_the_parameter(call, name):
    with pytest.raises(ValueError, match=name):
        call()


def test_rounds_converge_where_they_oscillated_before():
    """A 48 x 48 central crop of the bullet land, where the rounds used to oscillate (7, 6, 8, 7
    points flagged, stopped by the 4-round cap): the points left out of the fit only grow, so
    the rounds reach a fixed point, and the points reported are exactly those the last fit
    scores beyond the threshold (a subset of those left out of it)."""
    from roughgp.experiments.measured_surfaces import DATA, centre_crop
    from roughgp.io.measurement import read_measurement

    m = read_measurement(DATA / "sample-land.x3p")
    z = m.z[centre_crop("sample-land.x3p", 48)]
    found = detect_spurious(z, spacing=m.spacing, form="cylinder", seed=0)
    assert found.converged and found.rounds < 8
    assert list(found.history) == sorted(found.history)  # never shrinks
    assert found.history[-1] == found.history[-2] == int(found.excluded.sum())
    assert np.array_equal(found.flagged, np.abs(np.nan_to_num(found.scores)) > found.threshold)
    assert not np.any(found.flagged & ~found.excluded)
    capped = detect_spurious(z, spacing=m.spacing, form="cylinder", seed=0, rounds=2)
    assert not capped.converged and capped.rounds == 2  # the cap says it stopped short
    assert capped.history == found.history[:2]


def test_rounds_stop_at_once_on_a_clean_surface():
    found = detect_spurious(_clean((48, 48), seed=11), seed=0)
    if found.first_flagged.any():
        pytest.skip("this draw has a false alarm in the first round")
    assert found.converged and found.rounds == 1 and found.history == (0,)
