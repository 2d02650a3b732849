"""The Rao-Blackwellised share of the model check and the ranks' uniformity test
(roughgp.checking.ranks), calibrated on cases where the answer is known."""

from __future__ import annotations

import itertools

import numpy as np
import pytest

from roughgp.checking.ranks import (chance_within, outside_probability, pit_pvalue,
                                                 pit_values, rank_counts, share_interval,
                                                 uniform_rank_sd, verdict_within)


@pytest.mark.parametrize("values, measured", [
    ([0.3, 1.2, -0.5, 2.0, 0.9, 1.1, -1.0, 3.0, 0.1], 0.5),
    ([0.3, 1.2, 0.5, 2.0, 0.5, 1.1, 0.6, 3.0, 0.7], 0.5),      # ties count as neither side
    ([1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0], 0.5),      # all above
    ([1.0, 2.0, np.nan, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0], 5.5)])  # a NaN left out
def test_outside_probability_is_the_share_of_all_subsamples_outside(values, measured):
    """Brute force: every subset of n of the finite simulations, judged as the check judges."""
    finite = [v for v in values if np.isfinite(v)]
    for n in (1, 2, 4, 6):
        subsets = list(itertools.combinations(finite, n))
        brute = np.mean([min(s) > measured or max(s) < measured for s in subsets])
        above, below, ties, count = rank_counts(measured, values)
        assert count == len(finite) and above + below + ties == count
        assert outside_probability(above, below, count, n) == pytest.approx(brute, abs=1e-12)


def test_a_calibrated_check_has_mean_two_in_n_plus_one_and_a_smaller_scatter():
    for draws, n in ((19, 19), (39, 19), (199, 19), (99, 4)):
        below = np.arange(draws + 1)
        values = outside_probability(draws - below, below, draws, n)
        assert values.mean() == pytest.approx(2 / (n + 1), rel=1e-10)
    # the 0/1 verdict scatters by sqrt(0.1 * 0.9) = 0.30; the share from 199 draws by 0.21
    assert uniform_rank_sd(19) == pytest.approx(0.3, abs=1e-12)
    assert uniform_rank_sd(199) == pytest.approx(0.209, abs=0.001)
    assert uniform_rank_sd(100_000) == pytest.approx(0.203, abs=0.001)


def _iid_cases(scale, n_cases=400, draws=99, seed=3, plain=False):
    """Measured value N(0, 1), simulations N(0, scale^2): calibrated for scale 1. With
    ``plain``, also the 0/1 verdicts of the first 19 simulations of each case."""
    rng = np.random.default_rng(seed)
    measured = rng.normal(size=n_cases)
    sims = rng.normal(0, scale, (n_cases, draws))
    counts = [rank_counts(m, s) for m, s in zip(measured, sims)]
    above, below, ties, finite = (np.array(c) for c in zip(*counts))
    if plain:
        first = sims[:, :19]
        verdicts = (measured < first.min(axis=1)) | (measured > first.max(axis=1))
        return above, below, ties, finite, verdicts.astype(float)
    return above, below, ties, finite


def test_the_share_says_yes_on_a_calibrated_and_no_on_a_misspecified_model():
    above, below, ties, finite, plain = _iid_cases(1.0, plain=True)
    rb = outside_probability(above, below, finite, 19)
    share, low, high = share_interval(rb)
    assert low < 0.1 < high and abs(share - 0.1) < 0.03
    assert pit_pvalue(below, ties, finite) > 0.01
    # the 0/1 verdicts of the first 19 of the same draws: near the same mean (its sd over 400
    # cases is 1.5 %), a larger scatter per case (0.30 against 0.21)
    assert abs(plain.mean() - share) < 0.05
    assert rb.std() < 0.24 < 0.27 < plain.std()
    # simulations too narrow (half the sd): the measurement is outside far more often
    above, below, ties, finite = _iid_cases(0.5)
    rb = outside_probability(above, below, finite, 19)
    assert share_interval(rb)[1] > 0.3
    assert verdict_within(*share_interval(rb)[1:]) == "no"
    assert pit_pvalue(below, ties, finite) < 1e-6
    # too wide (twice the sd): hardly ever outside, and the PIT piles up near 0.5
    above, below, ties, finite = _iid_cases(2.0)
    rb = outside_probability(above, below, finite, 19)
    assert share_interval(rb)[2] < 0.07
    u = pit_values(below, ties, finite)
    assert np.mean(np.abs(u - 0.5) < 0.25) > 0.6 and pit_pvalue(below, ties, finite) < 1e-6


def test_seeded_cases_reproduce():
    first, again = _iid_cases(1.0, n_cases=20, seed=9), _iid_cases(1.0, n_cases=20, seed=9)
    for a, b in zip(first, again):
        np.testing.assert_array_equal(a, b)


def test_verdict_within_says_yes_no_and_undecided():
    assert verdict_within(0.08, 0.12) == "yes"
    assert verdict_within(0.01, 0.05) == "no" and verdict_within(0.14, 0.2) == "no"
    assert verdict_within(0.05, 0.12) == "undecided"


def test_bad_counts_are_refused_with_the_parameter_named():
    with pytest.raises(ValueError, match="n_simulations"):
        outside_probability(3, 2, 10, 0)
    with pytest.raises(ValueError, match="finite"):
        outside_probability(3, 2, 10, 19)
    with pytest.raises(ValueError, match="above and below"):
        outside_probability(8, 5, 10, 4)
    with pytest.raises(ValueError, match="1-D"):
        rank_counts(0.0, np.zeros((2, 2)))
    with pytest.raises(ValueError, match="at least 2"):
        share_interval([0.1])
    assert rank_counts(np.nan, [1.0, 2.0]) == (0, 0, 0, 2)


def test_chance_within_says_how_many_cases_the_target_needs():
    one_50, all_50 = chance_within(50, n_trials=3000)
    one_550, all_550 = chance_within(550, n_trials=600)
    # 50 cases: the share scatters by 2.9 %, so +- 3 % holds for about two thirds of the
    # parameters and almost never for all 13; 550 cases: the share scatters by 0.9 %
    assert 0.6 < one_50 < 0.75 and all_50 < 0.02
    assert one_550 > 0.99 and all_550 > 0.9
    assert chance_within(50, n_trials=200, seed=3) == chance_within(50, n_trials=200, seed=3)


@pytest.mark.parametrize("kwargs, message", [
    (dict(n_cases=0), "n_cases must be an integer >= 1"),
    (dict(n_cases=50, n_parameters=2.5), "n_parameters must be an integer >= 1"),
    (dict(n_cases=50, tolerance=0.0), r"tolerance must be in \(0, 1\)"),
])
def test_chance_within_refuses_bad_input(kwargs, message):
    with pytest.raises(ValueError, match=message):
        chance_within(**kwargs)


def test_pass_chance_is_the_binomial_yardstick():
    """At the level of 19 draws (10 % each) a model passes (at most 2 of 13 outside) on 87 % of
    maps; a check above its level passes less often; a chance outside [0, 1] is refused."""
    from roughgp.checking.ranks import pass_chance
    assert pass_chance() == pytest.approx(0.8661, abs=1e-4)
    assert pass_chance(chance=0.16) < pass_chance() < pass_chance(chance=0.05)
    assert pass_chance(n_parameters=13, most=13, chance=0.5) == pytest.approx(1.0)
    with pytest.raises(ValueError, match="chance must be in"):
        pass_chance(chance=1.5)
