"""The model file's numbers: the allowed range of each (:data:`RANGES`) and the checks of one
number or a list of them, which refuse a value of the wrong type or out of its range with a
message that names the field (:mod:`roughgp.surface_models.schema` uses them for every field).
"""

from __future__ import annotations

import math

__all__ = ["ModelFileError", "RANGES", "is_number", "number", "numbers_list"]

#: name -> (low, high, low included): the allowed range of each number (um, um^2, deg, 1/um)
RANGES = {
    "spacing_um": (1e-6, 1e6, True),  # the readers' step (roughgp.io.plausibility): 1 pm to 1 m
    "variance_um2": (0.0, 1e12, False),
    "weights_um2": (0.0, 1e12, False),
    "noise_variance_um2": (0.0, 1e12, True),
    "lambda_a_um": (0.0, 1e9, False), "lambda_b_um": (0.0, 1e9, False),
    "angle_deg": (-360.0, 360.0, True),
    "frequencies_per_um": (0.0, 1e9, True),
    "spectral_variances_per_um2": (0.0, 1e18, False),
    "mean_um": (-1e9, 1e9, True),
    "skewness": (-100.0, 100.0, True),
    "kurtosis": (1.0, 1e6, False),
    "s_um": (0.0, 1e9, False),
    "l_um": (0.0, 1e9, False),
    "degree": (0, 10, True),
    "psd_um4": (0.0, 1e30, True),
    "quantiles_um": (-1e9, 1e9, True),
    "tail_probability": (0.0, 0.25, False),
    "order_scores": (-40.0, 40.0, True),  # normal scores (roughgp.surface_models.order_scores)
    "frequency_min_per_um": (0.0, 1e9, False), "frequency_max_per_um": (0.0, 1e9, False),
    "frequencies_x_per_um": (-1e9, 1e9, True), "frequencies_y_per_um": (-1e9, 1e9, True),
    "bandwidths_a_per_um": (0.0, 1e9, False), "bandwidths_b_per_um": (0.0, 1e9, False),
    "axes_deg": (-360.0, 360.0, True),
    "anchors_x_um": (-1e9, 1e9, True), "anchors_y_um": (-1e9, 1e9, True),
    "feed_um": (0.0, 1e9, False),
    "lambda_um": (0.0, 1e9, False),
    "origin_um": (0.0, 1e9, True),
    "mark_um": (-1e9, 1e9, True),
    "shift_sd_um": (0.0, 1e9, True),
    "shift_rho": (0.0, 0.99, True),
    "depth_sd_um": (0.0, 1e9, True),
    "depth_rho": (0.0, 0.99, True),
    "lay_sd_um": (0.0, 1e9, True),
    "depth_length_um": (0.0, 1e9, False),
    "log_variance_sd": (0.0, 3.0, True), "log_lambda_a_sd": (0.0, 3.0, True),  # 3: x/ 20
    "log_lambda_b_sd": (0.0, 3.0, True), "angle_sd_deg": (0.0, 180.0, True),
}


class ModelFileError(ValueError):
    """A model file that is not a roughgp model, of another version, or incomplete."""


def is_number(value) -> bool:
    """A Python int or float, not a bool."""
    return isinstance(value, (int, float)) and not isinstance(value, bool)


def number(name, value, *, where=None):
    """``value`` as a float, refused unless it is a number (not a bool, not a string) within
    ``RANGES[name]``."""
    label = where or name
    if not is_number(value) and not _numpy_number(value):
        raise ModelFileError(f"{label} must be a number, got {value!r}")
    value = float(value)
    low, high, closed = RANGES[name]
    if not math.isfinite(value) or value > high or value < low or (value == low and not closed):
        bracket = "[" if closed else "("
        raise ModelFileError(f"{label} must be a finite number in {bracket}{low:g}, {high:g}], "
                             f"got {value!r}")
    return value


def _numpy_number(value) -> bool:
    import numpy as np
    return isinstance(value, np.number) and not isinstance(value, np.bool_)


def numbers_list(name, values, count=None):
    """``values`` (a list, tuple or array) as a list of floats, each checked by
    :func:`number` against ``RANGES[name]``, their count one of ``count`` when given."""
    if hasattr(values, "tolist"):
        values = values.tolist()
    if not isinstance(values, (list, tuple)) or not values:
        raise ModelFileError(f"{name} must be a non-empty list of numbers, got {values!r}")
    if count is not None and len(values) not in count:
        raise ModelFileError(f"{name} must hold {' or '.join(map(str, count))} values, got "
                             f"{len(values)}")
    return [number(name, v, where=f"{name}[{i}]") for i, v in enumerate(values)]
