"""roughgp.checking.auto_choice (issue 40, item 5): ``--model auto``'s heights chosen by the
out-of-sample check, the rung by the held-out prediction."""

from __future__ import annotations

import math

import numpy as np
import pytest

from roughgp.checking.auto_choice import LONG, SHORT, central_window, check_halves, choose_checked
from roughgp.gp.kernels import RotatedExponentialKernel
from roughgp.sampling import sample_grid


@pytest.fixture(scope="module")
def lognormal():
    """eq 18 through exp: heights of skewness about 2, which Gaussian simulations cannot
    reproduce on any half."""
    kernel = RotatedExponentialKernel(1.0, (4.0, 2.0), math.radians(30))
    return np.exp(0.6 * sample_grid(kernel, (64, 128), spacing=0.5, seed=2)[0])


def test_the_window_and_its_halves():
    assert central_window((1000, 300)) == ((1000 - LONG) // 2, (300 - SHORT) // 2, LONG,
                                           SHORT, "top")
    assert central_window((64, 128)) == (0, 0, 64, 128, "left")
    fitted, held = check_halves((64, 128))
    assert fitted.shape == held.shape == (64, 64) and not fitted.overlaps(held)
    fitted, held = check_halves((700, 200))
    assert fitted.rows == (94, 350) and held.rows == (350, 606) and fitted.cols == (0, 200)
    assert check_halves((20, 20)) == (None, None)


def test_skewed_heights_are_not_given_gaussian_simulations(lognormal):
    seen = []
    choice = choose_checked(lognormal, 0.5, rungs=("eq18",), n_blocks=4, seed=0,
                            on_check=seen.append)
    assert [c.marginal for c in choice.candidates] == ["gaussian", "johnson", "iaaft"]
    assert [c.marginal for c in seen] == ["gaussian", "johnson", "iaaft"]
    counts = {c.marginal: len(c.outside) for c in choice.candidates}
    assert {"Ssk", "Sku"} <= set(choice.candidates[0].outside)
    assert choice.marginal != "gaussian"
    assert counts[choice.marginal] == min(counts.values()) < counts["gaussian"]
    assert choice.model.marginal_method == choice.marginal
    assert choice.model.fit["out_of_sample_outside"] == counts
    assert choice.model.fit["heights_chosen_by"].startswith(f"{choice.marginal} heights: ")
    assert "chosen_by" in choice.model.fit and choice.chosen == "eq18"


def test_a_given_distribution_is_checked_not_chosen(lognormal):
    choice = choose_checked(lognormal, 0.5, marginal="gaussian", rungs=("eq18",), n_blocks=4)
    assert [c.marginal for c in choice.candidates] == ["gaussian"]
    assert choice.marginal == "gaussian" and choice.reason.startswith("given; ")
    with pytest.raises(ValueError, match="marginal must be None .* got 'lognormal'"):
        choose_checked(lognormal, 0.5, marginal="lognormal")
    with pytest.raises(ValueError, match="n_simulations must be an integer >= 9"):
        choose_checked(lognormal, 0.5, n_simulations=3)
