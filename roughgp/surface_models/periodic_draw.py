r"""Draws of the ``periodic-mark`` model (:mod:`roughgp.surface_models.periodic_model`).

A draw of ``shape`` is built in the frame where the marks repeat along x (the model's
``feed_direction_deg`` 90 transposes it):

0. the spreads of the shifts and of the depths, from their posterior (:func:`spread_draw`);
1. the marks' shifts :math:`s_k`, a stationary Gaussian AR(1) sequence over the mark index
   :math:`k` (standard deviation ``shift_sd_um``, lag-one correlation ``shift_rho``: an
   exponential covariance over the marks, the hierarchical layer of section 3.4's remedy);
2. the marks' depths :math:`d_k(y) = a_k + b_k(y)`: :math:`a_k` AR(1) over :math:`k`
   (``depth_sd_um``, ``depth_rho``), :math:`b_k` independent Gaussian functions along the lay
   (``lay_sd_um``) of squared-exponential correlation (:math:`\exp(-\tau_y^2 / \ell^2)`,
   :math:`\ell` = ``depth_length_um``), drawn by the FFT on a periodic grid at least four
   lengths longer than the field;
3. the trace: on each mark's window the mark moved by :math:`s_k` and sunk by
   :math:`d_k(y)` (:meth:`roughgp.metrology.feed_marks.FeedMarks.profile`);
4. eq 18 plus noise on top (the model's ``variance_um2`` ... ``noise_variance_um2``), drawn
   as the eq 18 rung draws.

Positions count from the fitted map's first point, the first mark at ``origin_um``.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from roughgp.metrology.feed_marks import FeedMarks

__all__ = ["mark_of", "ar1", "lay_field", "spread_draw", "ar1_across", "draw_periodic_model",
           "draw_periodic_profile", "roughness_model"]

_MAX_LAY_POINTS = 1 << 16


def mark_of(model) -> FeedMarks:
    """The model's mark as :class:`~roughgp.metrology.feed_marks.FeedMarks` with no shifts
    and depths (those are drawn)."""
    hp = model.hyperparameters
    return FeedMarks(float(hp["feed_um"]), float(hp["origin_um"]),
                     np.asarray(hp["mark_um"], dtype=np.float64), np.zeros(2), np.zeros(2),
                     float("nan"), float("nan"))


def ar1(count, sd, rho, rng, extra=()) -> np.ndarray:
    """``extra + (count,)`` stationary Gaussian AR(1) sequences of standard deviation ``sd``
    and lag-one correlation ``rho`` (along the last axis)."""
    white = rng.standard_normal(tuple(extra) + (count,))
    return sd * np.moveaxis(ar1_across(np.moveaxis(white, -1, 0), rho), 0, -1)


def lay_field(count, n, step, length, rng) -> np.ndarray:
    """``(count, n)`` independent unit-variance Gaussian functions along the lay at ``n``
    points ``step`` apart, of correlation :math:`\\exp(-\\tau^2/\\ell^2)`, ``length`` = ℓ
    (circulant embedding on a periodic grid at least ``n + 4 length / step`` long, at most
    2**16 points)."""
    size = int(min(_MAX_LAY_POINTS, max(2 * n, n + math.ceil(4 * length / step))))
    lag = np.minimum(np.arange(size), size - np.arange(size)) * step
    eigen = np.maximum(np.fft.rfft(np.exp(-(lag / length) ** 2)).real, 0.0)
    white = rng.standard_normal((count, size))
    return np.fft.irfft(np.fft.rfft(white, axis=-1) * np.sqrt(eigen), size, axis=-1)[:, :n]


def roughness_model(model):
    """The eq 18 rung of the roughness on top of the marks (the same spacing, the frame of the
    model's map)."""
    hp = model.hyperparameters
    keep = ("variance_um2", "lambda_a_um", "lambda_b_um", "angle_deg", "noise_variance_um2")
    return dataclasses.replace(model, equation="eq18", hyperparameters={k: hp[k] for k in keep},
                               marginal=None)


def draw_periodic_model(model, shape, spacing, rng, count) -> np.ndarray:
    """``count`` draws of ``model`` (a ``periodic-mark`` FittedModel) on ``shape`` (ny, nx) at
    ``spacing`` (dy, dx): shape ``(count, ny, nx)`` (module docstring)."""
    hp = model.hyperparameters
    across = hp["feed_direction_deg"] == 90
    ny, nx = (shape[1], shape[0]) if across else shape
    dy, dx = (spacing[1], spacing[0]) if across else spacing
    marks = mark_of(model)
    feed = marks.feed
    n_marks = int(math.ceil(nx * dx / feed)) + 3
    x = np.arange(nx) * dx
    traces = np.empty((count, ny, nx))
    for i in range(count):
        shift_sd = spread_draw(hp["shift_sd_um"], hp["marks_fitted"], rng)
        depth_sd = spread_draw(hp["depth_sd_um"], hp["marks_fitted"], rng)
        shifts = ar1(n_marks, min(shift_sd, feed / 4), hp["shift_rho"], rng)
        level = ar1(n_marks, depth_sd, hp["depth_rho"], rng)
        along = (np.zeros((n_marks, ny)) if ny == 1 or hp["lay_sd_um"] == 0 else
                 hp["lay_sd_um"] * lay_field(n_marks, ny, dy, hp["depth_length_um"], rng))
        drawn = dataclasses.replace(marks, shifts=shifts, depths=level)
        traces[i] = drawn.profile(x, depths=level[:, None] + along)
    if across:
        traces = np.swapaxes(traces, 1, 2)
    roughness = roughness_model(model).simulate(shape, spacing=spacing, n_samples=count,
                                                seed=rng)
    return float(hp.get("mean_um", 0.0)) + traces + roughness


def spread_draw(sd, n, rng) -> float:
    r"""A standard deviation drawn from its posterior given ``sd``, the spread (about their
    mean) of ``n`` values: :math:`\sigma^2 = n\,\mathrm{sd}^2 / \chi^2_{n-1}` (a normal
    sample under the scale-invariant prior :math:`p(\sigma) \propto 1/\sigma`), so that draws
    carry how little ``n`` marks say of it."""
    if sd == 0:
        return 0.0
    return float(sd * math.sqrt(n / rng.chisquare(n - 1)))


def draw_periodic_profile(model, n, spacing, rng, count) -> np.ndarray:
    """``count`` draws of a ``periodic-mark-profile`` model on ``n`` points ``spacing`` um apart:
    shape ``(count, n)``; the trace as :func:`draw_periodic_model`'s (one row), the exponential
    ACVF as its exact AR(1) recursion, white noise on top."""
    hp = model.hyperparameters
    marks = mark_of(model)
    n_marks = int(math.ceil(n * spacing / marks.feed)) + 3
    x = np.arange(n) * spacing
    a = math.exp(-spacing / hp["lambda_um"])
    out = np.empty((count, n))
    for i in range(count):
        shift_sd = spread_draw(hp["shift_sd_um"], hp["marks_fitted"], rng)
        depth_sd = spread_draw(hp["depth_sd_um"], hp["marks_fitted"], rng)
        shifts = ar1(n_marks, min(shift_sd, marks.feed / 4), hp["shift_rho"], rng)
        depths = ar1(n_marks, depth_sd, hp["depth_rho"], rng)
        trace = dataclasses.replace(marks, shifts=shifts, depths=depths).profile(x)
        rough = ar1(n, math.sqrt(hp["variance_um2"]), a, rng)
        noise = rng.normal(0.0, math.sqrt(hp["noise_variance_um2"]), n)
        out[i] = trace + rough + noise
    return float(hp.get("mean_um", 0.0)) + out


def ar1_across(lay, rho) -> np.ndarray:
    """Unit-variance fields ``lay`` (marks, points) made AR(1) over the marks with lag-one
    correlation ``rho`` (each mark's function along the lay keeps its correlation)."""
    out = np.empty_like(lay)
    out[0] = lay[0]
    scale = math.sqrt(1.0 - rho * rho)
    for k in range(1, lay.shape[0]):
        out[k] = rho * out[k - 1] + scale * lay[k]
    return out
