"""roughgp.experiments.turned_profile: figure 5's fit of eq 21 to a turned profile and the
simulations from it (a 2048-point profile, Q = 3; the chapter "Turned profiles" and the ledger
run the paper's)."""

import numpy as np
import pytest

from roughgp.experiments import turned_profile as tp
from roughgp.models import turned

N, Q, SEED = 2048, 3, 4


@pytest.fixture(scope="module")
def result():
    return tp.figure5_fit(N, n_components=Q, seed=SEED)


def test_the_fit_is_of_the_levelled_profile_and_cached(result):
    x, raw = turned.turned_profile(N, tp.SPACING, tp.PARAMS, seed=SEED)
    np.testing.assert_array_equal(result.raw, raw)
    np.testing.assert_array_equal(result.x, x)
    assert abs(np.polyfit(x, result.z, 1)[0]) < 1e-9            # the tilt is removed
    assert abs(np.polyfit(x, raw, 1)[0]) > 1e-4
    assert not result.z.flags.writeable and result.fit.n_points == N
    assert tp.figure5_fit(N, n_components=Q, seed=SEED) is result
    assert result.feed == tp.PARAMS.feed


def test_the_periodicity_is_extracted(result):
    assert result.period_error == pytest.approx(result.fit.dominant_period / result.feed - 1)
    assert abs(result.period_error) < 0.01


def test_the_candidates_are_reported(result):
    finals = result.optimised_log_likelihoods
    assert np.all(np.diff(finals) >= 0) and finals.size == sum(c.optimised
                                                                for c in result.fit.candidates)
    assert result.initial_log_likelihoods.size == len(result.fit.candidates)
    assert 1 <= result.n_distinct_optima <= finals.size
    assert finals[-1] == pytest.approx(result.fit.log_marginal_likelihood)


def test_simulations_are_symmetric_the_data_are_not(result):
    sims = tp.figure5_simulations(result, 12)
    assert sims.profiles.shape == (12, N) and sims.n_simulations == 12 and sims.seed == SEED + 1
    assert set(sims.values) == set(tp.PARAMETER_KEYS) == set(sims.inside)
    assert all(v.shape == (12,) for v in sims.values.values())
    assert sims.measured["Rsk"] > 0.3 and sims.measured["dale share"] > 0.5
    assert not sims.inside["Rsk"] and sims.inside["RSm"]
    lo, hi = sims.ranges["Rsk"]
    assert lo < 0.3 and lo <= hi
    np.testing.assert_array_equal(tp.figure5_simulations(result, 12).profiles, sims.profiles)
    assert tp.dale_share(np.array([0.0, 0.0, 0.0, 3.0])) == 0.75
