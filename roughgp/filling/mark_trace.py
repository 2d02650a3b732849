"""The feed marks of the map being filled, for a fill with a ``periodic-mark`` model (beyond the
paper; issue 41).

A fill with a periodic-mark model (:mod:`roughgp.surface_models.periodic_model`) kriges what
the marks leave: the map's own marks are found at the model's feed and direction
(:func:`roughgp.metrology.feed_marks.map_marks`: those of the mean profile across the lay;
each mark's depth row by row, :func:`~roughgp.metrology.feed_marks.row_depths`), their trace
is taken off the measured heights, the rest is filled with the model's eq 18 and noise, and the
trace is put back: in the holes the marks the map itself shows, moved and sunk as measured
around them. This module sits below the models and reads the model's fields by name.
"""

from __future__ import annotations

import math
import warnings

import numpy as np

from roughgp.metrology.feed_marks import map_marks, row_depths

__all__ = ["PERIODIC_EQUATIONS", "map_trace", "roughness_kernel"]

PERIODIC_EQUATIONS = ("periodic-mark",)


def map_trace(residual, model, spacing) -> np.ndarray:
    """The trace of the map's own marks on the grid of ``residual`` (heights after F, NaN in
    the holes), at the feed and in the direction of ``model`` (module docstring); a
    ``ValueError`` where the map holds no mark at that feed."""
    hp = model.hyperparameters
    across = hp["feed_direction_deg"] == 90
    h = residual.T if across else residual
    step = spacing[0] if across else spacing[1]
    with warnings.catch_warnings():
        warnings.filterwarnings("ignore", "Mean of empty slice")
        marks = map_marks(h, step, feed=float(hp["feed_um"]))
        depths = row_depths(h, marks, step)
        fallback = np.nanmean(depths)
    depths = np.where(np.isfinite(depths), depths, fallback)
    x = np.arange(h.shape[1]) * step
    trace = marks.profile(x, depths=depths)
    return trace.T if across else trace


def roughness_kernel(model):
    """The eq 18 kernel of the roughness on top of the marks."""
    from roughgp.gp.kernels import RotatedExponentialKernel
    hp = model.hyperparameters
    return RotatedExponentialKernel(hp["variance_um2"], (hp["lambda_a_um"], hp["lambda_b_um"]),
                                    math.radians(hp["angle_deg"]))
