"""Eq 18's exponential in one dimension plus noise, fitted by the Whittle likelihood
(roughgp.inference.exponential_profile): recovered on AR(1) profiles, bad input refused."""

import numpy as np
import pytest

from roughgp.inference.exponential_profile import fit_exponential_profile
from roughgp.surface_models.periodic_draw import ar1


def _profile(n, variance, length, noise, seed):
    rng = np.random.default_rng(seed)
    return ar1(n, np.sqrt(variance), np.exp(-1.0 / length), rng) + rng.normal(0, np.sqrt(noise), n)


@pytest.mark.parametrize("length", [2.0, 10.0])
def test_the_parameters_are_recovered(length):
    fits = [fit_exponential_profile(_profile(8192, 1.0, length, 0.1, seed), 1.0)
            for seed in range(5)]
    assert abs(np.median([f.variance for f in fits]) - 1.0) < 0.1
    assert abs(np.median([f.lengthscale for f in fits]) / length - 1) < 0.15
    assert abs(np.median([f.noise_variance for f in fits]) - 0.1) < 0.03


@pytest.mark.parametrize("z, words", [(np.zeros(64), "constant"), (np.ones(8), "16 points"),
                                      (np.r_[np.ones(20), np.nan], "complete")])
def test_bad_profiles_are_refused(z, words):
    with pytest.raises(ValueError, match=words):
        fit_exponential_profile(z, 1.0)
