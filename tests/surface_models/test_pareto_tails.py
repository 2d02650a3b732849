"""Generalized Pareto tails of the IAAFT quantile table (roughgp.surface_models.pareto_tails):
the probability-weighted moments recover a known tail, the table keeps the measured body and
continues it past the measured extremes, and bad input is refused by name."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.special
import scipy.stats

from roughgp.surface_models.pareto_tails import (
    TABLE_TAIL,
    pareto_quantile,
    pareto_tails_table,
    pwm_fit,
)


@pytest.mark.parametrize("c", [-0.3, 0.0, 0.2])
def test_pwm_recovers_a_known_tail(c):
    """scipy's shape c is -k (Hosking's sign)."""
    y = scipy.stats.genpareto(c=c, scale=2.0).rvs(20000, random_state=np.random.default_rng(3))
    sigma, k = pwm_fit(y)
    assert abs(k + c) < 0.04 and abs(sigma / 2.0 - 1.0) < 0.04
    f = np.array([0.5, 0.9, 0.99])
    np.testing.assert_allclose(pareto_quantile(sigma, k, f),
                               scipy.stats.genpareto(c=c, scale=2.0).ppf(f), rtol=0.06)


def _scores(n):
    t0 = scipy.special.ndtri(TABLE_TAIL)
    return np.linspace(t0, -t0, n)


def test_the_table_keeps_the_body_and_models_the_tails():
    h = np.random.default_rng(0).normal(size=200_000)
    q, tail, tails = pareto_tails_table(h, 1001)
    assert tail == TABLE_TAIL and len(q) == 1001 and np.all(np.diff(q) >= 0)
    scores = _scores(1001)
    body = np.abs(scores) < 1.6
    np.testing.assert_allclose(np.asarray(q)[body], np.quantile(
        h, scipy.special.ndtr(scores[body]), method="hazen"))
    at = np.array([-3.0, -2.0, 2.0, 3.0])
    np.testing.assert_allclose(np.interp(at, scores, q), at, rtol=0.03)
    # the GPD of a 5 % threshold (k > 0, a bounded tail) falls short of the normal's far tail:
    # 5 to 10 % at 4.5 sd, and its end (at 1e-7) short of 200 000 normal heights' extremes
    far = np.interp([-4.5, 4.5], scores, q)
    assert -4.5 < far[0] < -4.0 and 4.0 < far[1] < 4.5
    assert tails["low"][0] < 0 < tails["high"][0] and 0 < tails["high"][2] < 0.3


def test_a_heavy_upper_tail_stays_heavy():
    h = np.exp(0.6 * np.random.default_rng(1).normal(size=50_000))
    q, _, tails = pareto_tails_table(h, 1001)
    assert tails["high"][2] < 0.0       # k < 0: unbounded, heavier than exponential
    truth = np.exp(0.6 * 4.0)
    assert abs(np.interp(4.0, _scores(1001), q) / truth - 1.0) < 0.25


@pytest.mark.parametrize("heights, share, words", [
    (np.arange(100.0), 0.05, "need at least 400 measured heights"),
    (np.arange(1000.0), 0.6, "share must be in (0, 0.5)"),
    (np.r_[np.zeros(990), np.ones(10)], 0.05, "the low tail of the heights"),
])
def test_bad_input_is_refused_by_name(heights, share, words):
    with pytest.raises(ValueError, match=words.replace("(", r"\(").replace(")", r"\)")):
        pareto_tails_table(heights, 1001, share=share)
