"""Fits that stay in range (roughgp.surface_models.in_range): a length on the fit's bound or
far beyond the field is named, capped so that the model draws, and the fitted values kept."""

from __future__ import annotations

import numpy as np

from roughgp.surface_models.in_range import keep_in_range, range_findings
from roughgp.surface_models.model import FittedModel


def _model(lambda_a, lambda_b=3.0, variance=1.0):
    return FittedModel("eq18", {"variance_um2": variance, "lambda_a_um": lambda_a,
                                "lambda_b_um": lambda_b, "angle_deg": -45.0,
                                "noise_variance_um2": 0.01}, (1.0, 1.0))


def test_a_model_in_range_is_kept_as_it_is():
    model = _model(10.0)
    assert range_findings(model, (32, 32), 8) == []
    kept, notes = keep_in_range(model, (32, 32), 8)
    assert kept == model and notes == []


def test_a_length_on_the_bound_or_far_beyond_the_field_is_capped_and_draws():
    # the block fit's bound: 50 blocks of 8 points = 400 um; the field is 32 um
    for lam, words in ((400.0, "upper bound"), (200.0, "times the field's longer side")):
        model = _model(lam, variance=50.0)
        findings = range_findings(model, (32, 32), 8)
        assert len(findings) == 1 and words in findings[0]
        capped, notes = keep_in_range(model, (32, 32), 8)
        hp = capped.hyperparameters
        assert hp["lambda_a_um"] == 32.0 and hp["lambda_b_um"] == 3.0
        # the slope of the variogram along the lay, variance / lambda_a, is kept
        assert np.isclose(hp["variance_um2"] / 32.0, 50.0 / lam)
        assert capped.fit["fitted_hyperparameters"]["lambda_a_um"] == lam
        assert "replaced" in notes[-1] and capped.fit["range"] == notes
        assert np.all(np.isfinite(capped.simulate((32, 32), seed=1)))
