"""The model check of Std, a direction modulo 180 degrees: its rank test keeps 2 / (n + 1) on
isotropic and on laid surfaces (roughgp.checking.model_check.axial_frame)."""

from __future__ import annotations

import numpy as np
import pytest

from roughgp.checking.model_check import axial_frame, check_model
from roughgp.surface_models.model import FittedModel

N = 19   # simulations per check: 2 / 20 outside for a measurement drawn like them


def _outside_share(draw, trials, frame):
    """Share of ``trials`` checks in which the first of N + 1 directions from ``draw(rng)``
    lies beyond all N others once framed by ``frame(simulated, measured)``."""
    rng = np.random.default_rng(7)
    outside = 0
    for _ in range(trials):
        angles = draw(rng)
        sims = frame(angles[1:], angles[0])
        outside += bool(angles[0] < sims.min() or angles[0] > sims.max())
    return outside / trials


def _fold(angles):
    """Directions in (-90, 90], as Std is reported."""
    return 90.0 - (90.0 - np.asarray(angles)) % 180.0


def _measured_centred(simulated, measured):
    """Version 2's rule: the simulations unwrapped to within 90 degrees of the measured value."""
    return measured + (np.asarray(simulated) - measured + 90.0) % 180.0 - 90.0


@pytest.mark.parametrize("draw", [
    pytest.param(lambda rng: rng.uniform(-90.0, 90.0, N + 1), id="isotropic"),
    pytest.param(lambda rng: _fold(90.0 + rng.normal(0.0, 15.0, N + 1)), id="lay-across-the-fold"),
    pytest.param(lambda rng: _fold(30.0 + rng.normal(0.0, 5.0, N + 1)), id="lay-at-30-deg"),
])
def test_exchangeable_directions_are_outside_two_in_twenty(draw):
    # 4000 trials: a share of 0.1 scatters by 0.005
    share = _outside_share(draw, 4000, axial_frame)
    assert abs(share - 2 / (N + 1)) < 0.02, share


def test_the_measured_centred_rule_never_says_outside_on_an_isotropic_surface():
    # the control: centring on the measured value puts it in the middle of uniform directions
    share = _outside_share(lambda rng: rng.uniform(-90.0, 90.0, N + 1), 2000, _measured_centred)
    assert share < 0.01, share


def test_the_frame_keeps_the_measured_value_and_moves_simulations_by_half_turns():
    sims = np.array([88.0, -89.0, 85.0, np.nan, -80.0])
    framed = axial_frame(sims, -87.0)
    finite = np.isfinite(sims)
    assert np.isnan(framed[~finite]).all()
    turns = (framed[finite] - sims[finite]) / 180.0
    assert np.allclose(turns, np.round(turns))
    # clustered about the vertical: 88 and 85 become -92 and -95 next to the measured -87
    assert np.allclose(framed[finite], [-92.0, -89.0, -95.0, -80.0])
    assert framed[finite].max() - framed[finite].min() < 20.0
    assert np.array_equal(axial_frame(sims, np.nan), sims, equal_nan=True)


def test_check_model_reports_the_measured_std_and_frames_the_simulated():
    model = FittedModel("eq18", {"variance_um2": 1.0, "lambda_a_um": 6.0, "lambda_b_um": 6.0,
                                 "angle_deg": 0.0, "noise_variance_um2": 0.01}, (1.0, 1.0))
    z = model.simulate((48, 48), seed=3)
    std = check_model(model, z, n_simulations=19, seed=1, names=("Std",)).parameters[0]
    again = check_model(model, z, n_simulations=19, seed=1, names=("Std",)).parameters[0]
    assert -90.0 < std.measured <= 90.0
    assert np.array_equal(std.simulated, again.simulated)
    pooled = np.append(std.simulated, std.measured)
    assert pooled.max() - pooled.min() < 180.0
    assert std.outside == bool(std.measured < std.simulated.min()
                               or std.measured > std.simulated.max())


def test_the_check_says_when_it_shows_a_direction_turned_by_a_half_turn():
    # a lay across the fold at +-90 deg: some simulated directions come out near -90, the
    # measured one near +90, and the check shows them turned, with a note saying so
    model = FittedModel("eq18", {"variance_um2": 1.0, "lambda_a_um": 12.0, "lambda_b_um": 2.0,
                                 "angle_deg": 90.0, "noise_variance_um2": 0.01}, (1.0, 1.0))
    z = model.simulate((48, 48), seed=5)
    check = check_model(model, z, n_simulations=19, seed=2, names=("Std",))
    std = check.parameters[0]
    turned = bool((np.abs(std.simulated) > 90.0).any())
    assert turned == any("turned by 180 deg" in note for note in check.notes)
    assert turned, std.simulated     # this seed does turn some (else the test tests nothing)
