"""Prescribed roughness: ground surfaces with given ISO 25178-2 Sq, Sal, Str and Std (the
paper's future work [16]).

Modules: :mod:`~roughgp.targets.closed_form` (the closed form both ways between the four
parameters and eq 18 plus noise; measuring drawn surfaces) ←
:mod:`~roughgp.targets.calibration` (the closed form calibrated on a finite field by
simulation; :func:`~roughgp.targets.calibration.simulate_with_targets` draws the surfaces).
Their public names are re-exported here: ``from roughgp import targets;
targets.hyperparameters_for(...)``.

May import: :mod:`roughgp.common`, :mod:`roughgp.gp`, :mod:`roughgp.sampling`,
:mod:`roughgp.io`, :mod:`roughgp.metrology`, :mod:`roughgp.models`,
:mod:`roughgp.non_gaussian`.
"""

from roughgp.targets.calibration import Calibration, calibrate, simulate_with_targets
from roughgp.targets.closed_form import (
    MIN_GROOVE_LENGTHS,
    TARGET_NAMES,
    GroundHyperparameters,
    RoughnessTargets,
    achieved_parameters,
    as_targets,
    check_spacing,
    direction_difference,
    field_warning,
    finite_number,
    fold_direction,
    groove_lengths,
    hyperparameters_for,
    mean_direction,
    measure,
    predicted_targets,
    sq_prediction,
    summarize,
    surface_shape,
)

__all__ = ["TARGET_NAMES", "MIN_GROOVE_LENGTHS", "RoughnessTargets", "GroundHyperparameters",
           "as_targets", "hyperparameters_for", "predicted_targets", "measure",
           "achieved_parameters", "summarize", "direction_difference", "mean_direction",
           "fold_direction", "finite_number", "check_spacing", "surface_shape",
           "sq_prediction", "groove_lengths", "field_warning", "Calibration", "calibrate",
           "simulate_with_targets"]
