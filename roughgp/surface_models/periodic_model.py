r"""A periodic machined surface as a deterministic feed mark plus Gaussian processes: the
``periodic-mark`` rung (beyond the paper; issue 41, the remedy for figure 7 that section 3.4
names: "hierarchical GPs [36]").

Eq 22, the paper's model of a turned surface, is a stationary zero-mean GP: it gives every
spectral line a random amplitude and phase, so its simulations lose the mark's shape, the
periodicity over several feeds and the smooth dales (the chapter "Turned surfaces"). A turned,
milled, shaped or fly-cut surface is the tool's trace repeated at the feed, plus random
roughness. This model has three layers:

1. **the mark** :math:`m(u)` over one feed :math:`P` (a periodic mean function learned by
   folding the mean profile across the lay at the fitted feed,
   :func:`roughgp.metrology.feed_marks.feed_marks`);
2. **mark-to-mark variation**, the hierarchical layer: each mark's shift :math:`s_k` and depth
   :math:`a_k` are Gaussian AR(1) sequences over the mark index (an exponential covariance
   over :math:`k`), and each mark's depth varies along the lay around :math:`a_k` by an
   independent Gaussian function :math:`b_k(y)` of squared-exponential correlation, length
   :math:`\ell`. Their standard deviations and lag-one correlations are the moments of the
   per-mark estimates (shifts from the mean profile, depths row by row,
   :func:`~roughgp.metrology.feed_marks.row_depths`: :math:`a_k` their mean over the rows,
   :math:`b_k` the rest), over the marks that lie wholly in the map; :math:`\ell` is the lag
   at which the correlation of :math:`b_k` along the lay falls to :math:`e^{-1}`. A map holds
   few marks (eight on the chapter's turned surface), so the two spreads are uncertain: each
   draw takes its own, from their posterior given the ``marks_fitted`` marks
   (:func:`~roughgp.surface_models.periodic_draw.spread_draw`);
3. **the roughness on top**: eq 18 plus noise (eq 8) fitted by the debiased Whittle likelihood
   (:func:`~roughgp.inference.whittle_fit.fit_whittle`) to the residual, the map less the
   fitted trace, on a central crop of at most :data:`RESIDUAL_POINTS` points (the residual is
   stationary; a larger crop changes the fit by less than its own error and costs minutes).
   The residual's mean along the lay is removed first: it is what the trace misses of the
   mean profile (on the chapter's turned surface 0.07 % of its variance, at the cusps, where
   the tool's arcs meet at depths the rigid copies of one mark do not follow), constant along
   the lay, and eq 18 would take it for a roughness of correlation lengths tens of times the
   real one's. It is not drawn; ``fit["trace_misfit_um2"]`` keeps its variance.

The direction of the feed is the axis whose mean profile holds the more reproducible mark
(``lay="auto"``), or given. Where neither holds a mark, :func:`fit_periodic_model` raises
:class:`~roughgp.metrology.feed_marks.NoPeriodError`, whose message says so (the command falls
back to the stationary ladder). Draws: :mod:`roughgp.surface_models.periodic_draw`.

A profile (:func:`fit_periodic_profile`, rung ``periodic-mark-profile``) has the same first two
layers without the lay, and eq 18's exponential ACVF in one dimension plus noise on top
(:func:`roughgp.inference.exponential_profile.fit_exponential_profile`).
"""

from __future__ import annotations

import dataclasses
import math
import time
import warnings

import numpy as np

from roughgp.common.checks import surface_array
from roughgp.common.grid import normalize
from roughgp.inference.exponential_profile import fit_exponential_profile
from roughgp.inference.whittle_fit import fit_whittle
from roughgp.metrology.feed_marks import (
    FeedMarks,
    NoPeriodError,
    feed_marks,
    map_marks,
    row_depths,
)
from roughgp.metrology.filters import Texture
from roughgp.surface_models.chain import measured_chain
from roughgp.surface_models.model import FittedModel

__all__ = ["RESIDUAL_POINTS", "PeriodicModelFit", "fit_periodic_model",
           "fit_periodic_profile", "find_mark", "NoPeriodError", "lag_one", "lay_length"]

#: the most points of the residual that eq 18 is fitted on (a central crop)
RESIDUAL_POINTS = 1 << 18
_RHO_MAX = 0.95


@dataclasses.dataclass(frozen=True)
class PeriodicModelFit:
    """What :func:`fit_periodic_model` returns: the model, the measurement's chain, the marks
    found (in the frame where they repeat along x), their depths row by row ``(K, n_lay)``
    and the residual (the heights after F less the fitted trace, the model's frame)."""

    model: FittedModel
    texture: Texture
    marks: FeedMarks
    depths: np.ndarray
    residual: np.ndarray


def lag_one(values) -> float:
    """The lag-one correlation of ``values`` (marks along the first axis, NaN ignored) about
    their mean, clipped to [0, 0.95]: the AR(1) coefficient of the marks."""
    v = np.asarray(values, dtype=np.float64)
    v = v - np.nanmean(v)
    pairs = v[1:] * v[:-1]
    var = np.nanmean(v * v)
    if not var > 0 or not np.isfinite(pairs).any():
        return 0.0
    return float(np.clip(np.nanmean(pairs) / var, 0.0, _RHO_MAX))


def lay_length(depths, step) -> float:
    """The lag (um) at which the correlation of the marks' depths along the lay (``(K, n)``,
    mean removed, pooled over the marks) first falls to :math:`e^{-1}`, interpolated; the
    lay's whole length where it never does."""
    d = np.asarray(depths, dtype=np.float64)
    d = d - np.nanmean(d)
    n = d.shape[1]
    var = np.nanmean(d * d)
    if n < 2 or not var > 0:
        return float(max(n, 1) * step)
    previous = 1.0
    for lag in range(1, n):
        r = np.nanmean(d[:, :-lag] * d[:, lag:]) / var
        if r <= math.exp(-1.0):
            return float(step * (lag - 1 + (previous - math.exp(-1.0)) / (previous - r)))
        previous = r
    return float(n * step)


def _central_crop(residual, limit):
    ny, nx = residual.shape
    if ny * nx <= limit:
        return residual
    side = int(math.sqrt(limit))
    cy, cx = min(ny, max(side, limit // nx)), min(nx, max(side, limit // ny))
    cy, cx = min(cy, limit // cx), cx
    y0, x0 = (ny - cy) // 2, (nx - cx) // 2
    return residual[y0:y0 + cy, x0:x0 + cx]


def _whole_marks(marks: FeedMarks, length):
    """Which marks lie wholly inside [0, length)."""
    lo = marks.centres - marks.feed / 2
    return (lo >= -1e-9) & (lo + marks.feed <= length + 1e-9)


def _marks_both_ways(heights, dx, dy, feed, lay):
    frames = {"x": (heights, dx, dy), "y": (heights.T, dy, dx)}
    found, refusals = {}, []
    for name in (("x", "y") if lay == "auto" else (lay,)):
        h, step, _ = frames[name]
        try:
            found[name] = map_marks(h, step, feed=feed)
        except NoPeriodError as exc:
            refusals.append(f"along {name}: {exc}")
    return frames, found, refusals


def find_mark(z, spacing=1.0, *, form="plane", degree=2, axis="auto"):
    """``(direction, marks)`` of the more reproducible feed mark of the map ``z`` after the
    F-operator, along ``"x"`` or ``"y"``, or None where neither direction holds one: the test
    of :func:`fit_periodic_model` alone (a fraction of a second), for ``--model auto``."""
    arr = surface_array(z)
    _, (dy, dx) = normalize(arr.shape, spacing)
    with warnings.catch_warnings():
        warnings.filterwarnings("ignore", "Mean of empty slice")
        _, _, heights = measured_chain(arr, (dy, dx), form, None, None, degree, axis,
                                       "form-removed")
        _, found, _ = _marks_both_ways(heights, dx, dy, None, "auto")
    if not found:
        return None
    direction = max(found, key=lambda n: found[n].reproducibility)
    return direction, found[direction]


def fit_periodic_model(z, spacing=1.0, *, form="plane", s=None, l=None, degree=2, axis="auto",
                       feed=None, lay="auto", data=None, device=None) -> PeriodicModelFit:
    """Fit the ``periodic-mark`` model to a measured surface ``z[iy, ix]`` (um, NaN where
    unmeasured; module docstring).

    Args:
        spacing: scalar or ``(dy, dx)``, um.
        form, s, l, degree, axis: the operators, as
            :func:`~roughgp.surface_models.fit.fit_surface_model` (the model describes the
            heights after F).
        feed: the feed in um when known (else found from the data).
        lay: ``"auto"``, ``"x"`` (the marks repeat along x: they run along y) or ``"y"``.
        data: the source's description, kept in the model.
        device: where the Whittle fit of the roughness runs (:mod:`roughgp.common.device`).

    Raises:
        NoPeriodError: no direction holds a reproducible feed mark.
    """
    with warnings.catch_warnings():   # rows, columns or marks with no measured point: NaN,
        warnings.filterwarnings("ignore", "Mean of empty slice")        # handled below
        warnings.filterwarnings("ignore", "Degrees of freedom <= 0")
        return _fit_periodic_model(z, spacing, form, s, l, degree, axis, feed, lay, data, device)


def _fit_periodic_model(z, spacing, form, s, l, degree, axis, feed, lay, data, device):
    if lay not in ("auto", "x", "y"):
        raise ValueError(f"lay must be 'auto', 'x' or 'y', got {lay!r}")
    arr = surface_array(z)
    _, (dy, dx) = normalize(arr.shape, spacing)
    start = time.perf_counter()
    texture, cutoffs, heights = measured_chain(arr, (dy, dx), form, s, l, degree, axis,
                                               "form-removed")
    frames, found, refusals = _marks_both_ways(heights, dx, dy, feed, lay)
    if not found:
        raise NoPeriodError("; ".join(refusals))
    direction = max(found, key=lambda n: found[n].reproducibility)
    marks = found[direction]
    h, step, lay_step = frames[direction]
    depths = row_depths(h, marks, step)
    whole = _whole_marks(marks, h.shape[1] * step)
    if whole.sum() < 2:
        whole = np.isfinite(depths).any(axis=1)
    mean_depth = np.nanmean(depths[whole])
    filled = np.where(np.isfinite(depths), depths, mean_depth)
    x = np.arange(h.shape[1]) * step
    residual = h - marks.profile(x, depths=filled)
    misfit = np.nanmean(residual, axis=0)          # what the trace misses of the mean profile
    rough = residual - (misfit[None, :] if h.shape[0] > 1 else 0.0)
    fit = fit_whittle(_central_crop(rough, RESIDUAL_POINTS), spacing=(lay_step, step),
                      device=device)
    g = fit.groove
    angle = math.degrees(g.angle)
    if direction == "y":       # the residual's frame is transposed: x <-> y
        angle = 90.0 - angle
    inner = depths[whole]
    level = np.nanmean(inner, axis=1)              # each mark's depth
    along = inner - level[:, None]                 # and its variation along the lay
    hyper = {"feed_um": marks.feed, "feed_direction_deg": 0 if direction == "x" else 90,
             "origin_um": float(marks.origin % marks.feed),
             "mark_um": [float(v) for v in marks.mark],
             "shift_sd_um": float(min(np.std(marks.shifts[whole]), marks.feed / 4)),
             "shift_rho": lag_one(marks.shifts[whole]),
             "depth_sd_um": float(np.std(level)),
             "depth_rho": lag_one(level),
             "lay_sd_um": float(np.nanstd(along)) if h.shape[0] > 1 else 0.0,
             "depth_length_um": lay_length(along, lay_step),
             "marks_fitted": int(max(whole.sum(), 2)),
             "variance_um2": float(g.variance), "lambda_a_um": float(g.lengthscales[0]),
             "lambda_b_um": float(g.lengthscales[1]),
             "angle_deg": float((angle + 90.0) % 180.0 - 90.0),
             "noise_variance_um2": float(fit.noise_variance),
             "mean_um": float(np.nanmean(heights))}
    missing = ~np.isfinite(heights)
    described = {**(data or {}), "shape": list(arr.shape), "spacing_um": [dy, dx],
                 "missing_fraction": float(missing.mean()),
                 "points_used": int((~missing).sum())}
    how = {"method": "feed mark folded at the fitted feed, per-mark shifts and depths as "
                     "AR(1) Gaussian sequences, eq 18 on the residual by the debiased Whittle "
                     "likelihood (roughgp.surface_models.periodic_model)",
           "marks": int(whole.sum()), "mark_reproducibility": round(marks.reproducibility, 4),
           "mark_explained": round(marks.explained, 4),
           "trace_misfit_um2": float(np.nanvar(misfit)),
           "residual_log_likelihood": fit.log_likelihood,
           "seconds": round(time.perf_counter() - start, 2)}
    model = FittedModel("periodic-mark", hyper, (dy, dx), None, tuple(texture.operators),
                        cutoffs, described, how, "form-removed")
    return PeriodicModelFit(model, texture, marks, depths, residual)


def fit_periodic_profile(z, spacing=1.0, *, form="plane", s=None, l=None, feed=None,
                         data=None) -> PeriodicModelFit:
    """Fit the ``periodic-mark-profile`` model to a complete measured profile ``z[ix]`` (um;
    module docstring): the marks of the profile after F (a least-squares line for
    ``form="plane"``), their shifts' and depths' spreads and lag-one correlations over the
    whole marks, and the exponential ACVF plus noise on the rest. ``depths`` of the result is
    ``(K, 1)``.

    Raises:
        NoPeriodError: the profile holds no reproducible feed mark.
    """
    arr = np.asarray(z, dtype=np.float64)
    if arr.ndim != 1:
        raise ValueError(f"z must be a profile z[ix], got shape {arr.shape}")
    missing = int(np.count_nonzero(~np.isfinite(arr)))
    if missing:
        raise ValueError(f"the profile has {missing} missing (NaN) point(s); the periodic-mark "
                         f"fit of a profile needs a complete profile (fill or crop them first)")
    dx = float(np.ravel(spacing)[-1])
    if not (math.isfinite(dx) and dx > 0):
        raise ValueError(f"spacing must be > 0, got {spacing!r}")
    start = time.perf_counter()
    texture, cutoffs, heights = measured_chain(arr, dx, form, s, l, 2, "auto", "form-removed")
    marks = feed_marks(heights, dx, feed=feed)
    x = np.arange(arr.size) * dx
    whole = _whole_marks(marks, arr.size * dx)
    residual = heights - heights.mean() - marks.profile(x)
    rough = fit_exponential_profile(residual, dx)
    hyper = {"feed_um": marks.feed, "origin_um": float(marks.origin % marks.feed),
             "mark_um": [float(v) for v in marks.mark],
             "shift_sd_um": float(min(np.std(marks.shifts[whole]), marks.feed / 4)),
             "shift_rho": lag_one(marks.shifts[whole]),
             "depth_sd_um": float(np.std(marks.depths[whole])),
             "depth_rho": lag_one(marks.depths[whole]),
             "marks_fitted": int(max(whole.sum(), 2)),
             "variance_um2": rough.variance, "lambda_um": rough.lengthscale,
             "noise_variance_um2": rough.noise_variance, "mean_um": float(heights.mean())}
    described = {**(data or {}), "shape": [arr.size], "spacing_um": [dx],
                 "missing_fraction": 0.0, "points_used": int(arr.size)}
    how = {"method": "feed mark folded at the fitted feed, per-mark shifts and depths as "
                     "AR(1) Gaussian sequences, the exponential ACVF plus noise on the residual "
                     "by the Whittle likelihood (roughgp.surface_models.periodic_model)",
           "marks": int(whole.sum()), "mark_reproducibility": round(marks.reproducibility, 4),
           "mark_explained": round(marks.explained, 4),
           "residual_log_likelihood": rough.log_likelihood,
           "seconds": round(time.perf_counter() - start, 2)}
    model = FittedModel("periodic-mark-profile", hyper, (dx,), None, tuple(texture.operators),
                        cutoffs, described, how, "form-removed")
    return PeriodicModelFit(model, texture, marks, marks.depths[:, None], residual)
