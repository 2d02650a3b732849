"""The ``eq18-field`` model's parameter fields on a grid, and its draws
(:mod:`roughgp.surface_models.field_model` says how the model is fitted and why it is drawn
so). Apart from the fit, so that :class:`~roughgp.surface_models.model.FittedModel` can draw
it without importing the fit's chain."""

from __future__ import annotations

import math

import numpy as np

from roughgp.common.grid import normalize
from roughgp.inference.random_effects import wrap_angle

__all__ = ["FIELD_KERNELS", "field_at", "draw_field_model"]

#: stationary kernels blended per draw (relative covariance error about 0.02 at K = 8)
FIELD_KERNELS = 8


def _along(positions, anchors):
    """Lower index, upper index and weight of the linear interpolation at ``positions``
    between ``anchors``: continued linearly for half an anchor interval beyond the outer
    anchors (to the edge of the outer tiles), held constant further out."""
    anchors = np.asarray(anchors, dtype=np.float64)
    if anchors.size == 1:
        zeros = np.zeros(positions.shape, dtype=int)
        return zeros, zeros, np.zeros(positions.shape)
    x = np.clip(positions, anchors[0] - (anchors[1] - anchors[0]) / 2,
                anchors[-1] + (anchors[-1] - anchors[-2]) / 2)
    upper = np.clip(np.searchsorted(anchors, x, side="right"), 1, anchors.size - 1)
    lower = upper - 1
    weight = (x - anchors[lower]) / (anchors[upper] - anchors[lower])
    return lower, upper, weight


def _bilinear(grid, rows, cols):
    (r0, r1, wr), (c0, c1, wc) = rows, cols
    top = grid[r0][:, c0] * (1 - wc) + grid[r0][:, c1] * wc
    bottom = grid[r1][:, c0] * (1 - wc) + grid[r1][:, c1] * wc
    return top * (1 - wr)[:, None] + bottom * wr[:, None]


def _interpolated(grid, hp, y, x, step):
    """``grid`` (anchors_y x anchors_x) at the positions ``y`` and ``x``: bilinear, or with
    ``step`` (``{"axis", "at_um"}``) bilinear on each side of the boundary from that side's
    anchors alone."""
    anchors_y, anchors_x = np.asarray(hp["anchors_y_um"]), np.asarray(hp["anchors_x_um"])
    if step is None:
        return _bilinear(grid, _along(y, anchors_y), _along(x, anchors_x))
    across_x = step["axis"] == "x"
    anchors = anchors_x if across_x else anchors_y
    positions = x if across_x else y
    beyond = anchors > step["at_um"]
    sides = []
    for side in (~beyond, beyond):
        part = grid[:, side] if across_x else grid[side]
        if across_x:
            sides.append(_bilinear(part, _along(y, anchors_y), _along(x, anchors_x[side])))
        else:
            sides.append(_bilinear(part, _along(y, anchors_y[side]), _along(x, anchors_x)))
    far = positions > step["at_um"]
    return np.where(far[None, :] if across_x else far[:, None], sides[1], sides[0])


def field_at(model, shape, spacing=None) -> dict:
    """The model's parameter fields on a grid of ``shape`` (``(ny, nx)``) at ``spacing``
    (default the model's), positions from the fitted map's first point (a field with a
    step jumps at its boundary: :mod:`roughgp.surface_models.field_model`): ``variance``,
    ``lambda_a``, ``lambda_b`` (um^2, um), ``angle`` (radians) and ``noise_variance``,
    each an array of ``shape`` (module docstring)."""
    if model.equation != "eq18-field":
        raise ValueError(f"field_at needs an eq18-field model, got {model.equation}")
    shape, (dy, dx) = normalize(shape, model.spacing if spacing is None else spacing)
    hp = model.hyperparameters
    y, x = np.arange(shape[0]) * dy, np.arange(shape[1]) * dx
    steps = hp.get("steps", {})
    out = {}
    for name, key in (("variance", "variance_um2"), ("lambda_a", "lambda_a_um"),
                      ("lambda_b", "lambda_b_um")):
        out[name] = np.exp(_interpolated(np.log(np.asarray(hp[key], dtype=np.float64)), hp,
                                         y, x, steps.get(key)))
    angles = np.radians(np.asarray(hp["angle_deg"], dtype=np.float64))
    mean = 0.5 * math.atan2(float(np.sin(2 * angles).sum()), float(np.cos(2 * angles).sum()))
    out["angle"] = mean + _interpolated(wrap_angle(angles - mean), hp, y, x,
                                        steps.get("angle_deg"))
    out["noise_variance"] = np.full(shape, float(hp["noise_variance_um2"]))
    return out


def draw_field_model(model, shape, spacing, rng, count) -> np.ndarray:
    """``count`` draws (``(count, ny, nx)``) of the model on a grid of ``shape`` at
    ``spacing`` (module docstring: the K-kernel blend, then the noise)."""
    from roughgp.models.nonstationary import ParameterField, sample_nonstationary
    values = field_at(model, shape, spacing)
    field = ParameterField(**values)
    return sample_nonstationary(shape, spacing, field, n_kernels=FIELD_KERNELS,
                                n_samples=count, seed=rng)
