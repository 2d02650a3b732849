"""Tests of roughgp.common.numerics: the start perturbation that finds set-up-dependent verdicts."""

from __future__ import annotations

import numpy as np
import pytest
from scipy import optimize

from roughgp.common import numerics


def test_unset_or_zero_leaves_the_start_bit_for_bit(monkeypatch):
    start = np.array([0.1, -2.0, 3.5])
    monkeypatch.delenv(numerics.ENV, raising=False)
    assert numerics.perturbed_start(start).tobytes() == start.tobytes()
    monkeypatch.setenv(numerics.ENV, "0")
    assert numerics.perturbed_start(start).tobytes() == start.tobytes()


def test_a_seed_moves_the_start_by_about_the_jitter_reproducibly_and_within_bounds(monkeypatch):
    start = np.zeros(2000)
    monkeypatch.setenv(numerics.ENV, "3")
    moved = numerics.perturbed_start(start)
    assert 0.9 * numerics.JITTER < moved.std() < 1.1 * numerics.JITTER
    assert np.array_equal(moved, numerics.perturbed_start(start))      # the same seed, the same
    monkeypatch.setenv(numerics.ENV, "4")
    assert not np.array_equal(moved, numerics.perturbed_start(start))  # another seed, another
    lower, upper = np.zeros(2000), np.full(2000, np.inf)
    assert numerics.perturbed_start(start, lower, upper).min() >= 0.0


@pytest.mark.parametrize("text", ["-1", "x", "1.5", str(2**32)])
def test_a_bad_seed_is_refused_naming_the_variable(monkeypatch, text):
    monkeypatch.setenv(numerics.ENV, text)
    with pytest.raises(ValueError, match=numerics.ENV):
        numerics.start_jitter()


def _double_well_end(seed, monkeypatch):
    """Where L-BFGS-B ends on 1e6 (x^2 - 1)^2 from the barrier top x = 0: a fragile verdict."""
    monkeypatch.setenv(numerics.ENV, str(seed))
    x0 = numerics.perturbed_start(np.zeros(1))
    result = optimize.minimize(lambda x: 1e6 * (x[0] ** 2 - 1) ** 2, x0, method="L-BFGS-B")
    return float(result.x[0])


def test_the_jitter_exposes_a_verdict_that_depends_on_the_start(monkeypatch):
    """From the barrier top the unperturbed optimiser falls into the right-hand well (its finite
    difference happens to lean that way); jittered starts fall into both wells, so a claim 'the
    optimum is the right-hand well' would flip between set-ups."""
    assert round(_double_well_end(0, monkeypatch), 3) == 1.0
    ends = {round(_double_well_end(seed, monkeypatch), 3) for seed in range(1, 9)}
    assert ends == {-1.0, 1.0}


def test_the_setup_reports_the_jitter_and_the_blas_threads(monkeypatch):
    monkeypatch.setenv(numerics.ENV, "7")
    now = numerics.setup()
    assert now["start_jitter"] == 7 and now["blas_threads"] >= 1
