"""The operator chain a surface model sits in, and what a fit keeps of the measured heights.

A model describes the surface at one stage of the measurement's chain (form removal F, then the
S- and L-filters; :mod:`roughgp.surface_models.model`). :func:`measured_chain` applies the chain
to a measurement and returns the heights a model of a stage is fitted to; :func:`rest_of_chain`
puts a simulation of the model through the rest of it, holes included, exactly as the
measurement went (like with like: :mod:`roughgp.surface_models.fit` says why), before
:func:`roughgp.checking.model_check.check_model` compares the two. :func:`marginal_of` (the
height distribution a model keeps), :func:`form_removed_surface` and :func:`described_data`
are shared by the fits of every rung (:mod:`roughgp.surface_models.fit`).
"""

from __future__ import annotations

import numpy as np

from roughgp.common.checks import check_varies, surface_array
from roughgp.common.grid import normalize
from roughgp.metrology.filters import Texture, surface_texture
from roughgp.surface_models.model import FittedModel
from roughgp.surface_models.schema import STAGES

__all__ = ["MARGINALS", "marginal_of", "apply_operators", "rest_of_chain", "form_removed",
           "measured_chain", "form_removed_surface", "described_data"]


def apply_operators(z, spacing, cutoffs, *, simulated=False) -> Texture:
    """The model's operators (``model.cutoffs``) applied to heights ``z``: the F-operator, then
    the S- and L-filters. ``simulated=True`` is for a simulation of a model of stage
    ``"filtered"``, which describes the heights *after* the operators: only the least-squares
    plane (or line) is removed from it (:func:`rest_of_chain` decides)."""
    if simulated:
        return surface_texture(z, spacing, form="plane", s=None, l=None)
    return surface_texture(z, spacing, form=cutoffs.get("form", "plane"),
                           s=cutoffs.get("s_um"), l=cutoffs.get("l_um"),
                           degree=int(cutoffs.get("degree", 2)),
                           axis=cutoffs.get("axis", "auto"))


def rest_of_chain(model: FittedModel, draw, spacing, holes=None) -> Texture:
    """A simulation ``draw`` of ``model`` put through the operator chain as the measurement
    went through it, from the model's stage on: the measurement's ``holes`` (a boolean map,
    or None) first, then, for a model of stage ``"form-removed"``, the F-operator, S- and
    L-filters of ``model.cutoffs`` exactly as on the measurement (the form fitted to the
    measured points only, the filters NaN-aware); for stage ``"filtered"``, the least-squares
    plane alone."""
    draw = np.asarray(draw, dtype=np.float64)
    if holes is not None:
        draw = np.where(holes, np.nan, draw)
    return apply_operators(draw, spacing, model.cutoffs, simulated=model.stage == "filtered")


def form_removed(z, spacing, cutoffs) -> Texture:
    """The F-operator of ``cutoffs`` alone on ``z``: the heights a model of stage
    ``"form-removed"`` describes (``.sl``)."""
    return apply_operators(z, spacing, {**cutoffs, "s_um": None, "l_um": None})


#: the height distributions a fitted model may keep
MARGINALS = ("gaussian", "johnson", "iaaft")


def marginal_of(heights, method, filtered=None, l_um=None):
    """The ``marginal`` field of a model of ``heights`` (NaN where unmeasured): None for
    ``"gaussian"``, their skewness and kurtosis for ``"johnson"``, their quantile function for
    ``"iaaft"`` (:mod:`roughgp.surface_models.iaaft`); with an L-filter (``l_um``) the IAAFT
    marginal is that of the ``filtered`` heights, matched in the band the filter passes
    (``above_l_um``)."""
    if method not in MARGINALS:
        raise ValueError(f"marginal must be one of {list(MARGINALS)}, got {method!r}")
    if method == "gaussian":
        return None
    if method == "iaaft":
        from roughgp.surface_models import iaaft
        banded = filtered is not None and l_um is not None
        quantiles, tail = iaaft.quantile_table(filtered if banded else heights)
        return {"method": "iaaft", "quantiles_um": quantiles, "tail_probability": tail,
                "iterations": iaaft.ITERATIONS, **({"above_l_um": float(l_um)} if banded
                                                   else {})}
    h = heights[np.isfinite(heights)]
    h = h - h.mean()
    sd = float(np.sqrt(np.mean(h * h)))
    skewness = float(np.mean(h ** 3) / sd ** 3)
    kurtosis = float(np.mean(h ** 4) / sd ** 4)
    return {"skewness": skewness, "kurtosis": max(kurtosis, skewness ** 2 + 1.01)}


def _cutoffs(form, s, l, degree, axis):
    return {"form": form, "s_um": s, "l_um": l, "degree": degree, "axis": axis}


def measured_chain(arr, spacing, form, s, l, degree, axis, stage):
    """The measurement's chain (its cut-offs resolved), and the heights the model of ``stage``
    is fitted to: after F alone (``"form-removed"``) or after every operator; a ``ValueError``
    where they are constant (:func:`roughgp.common.checks.check_varies`: no model of a flat
    map)."""
    if stage not in STAGES:
        raise ValueError(f"stage must be one of {list(STAGES)}, got {stage!r}")
    texture = surface_texture(arr, spacing, form=form, s=s, l=l, degree=degree, axis=axis)
    cutoffs = _cutoffs(form, texture.cutoffs.s, texture.cutoffs.l, degree, axis)
    heights = texture.sl if stage == "filtered" else form_removed(arr, spacing, cutoffs).sl
    check_varies("the heights after the F-operator" + (" and the filters" if stage == "filtered"
                                                       else ""), heights, arr)
    return texture, cutoffs, heights


def form_removed_surface(z, spacing, form, s, l, degree, axis, marginal, *, name, min_side):
    """``(arr, (dy, dx), texture, cutoffs, heights)``: the checks shared by the models fitted to
    a surface's form-removed heights (``marginal`` one of :data:`MARGINALS`, ``z`` a surface of
    at least ``min_side`` points a side: a ``ValueError`` naming the model ``name``
    otherwise), then :func:`measured_chain` of stage ``"form-removed"``."""
    if marginal not in MARGINALS:
        raise ValueError(f"marginal must be one of {list(MARGINALS)}, got {marginal!r}")
    arr = surface_array(z)
    if min(arr.shape) < min_side:
        raise ValueError(f"the {name} model needs a surface of at least {min_side} x "
                         f"{min_side} points, got {arr.shape}")
    _, (dy, dx) = normalize(arr.shape, spacing)
    texture, cutoffs, heights = measured_chain(arr, (dy, dx), form, s, l, degree, axis,
                                               "form-removed")
    return arr, (dy, dx), texture, cutoffs, heights


def described_data(data, shape, spacing, measured) -> dict:
    """The model's ``data``: the source's description ``data`` plus the shape, spacing,
    missing share and points used (``measured``: the map of measured points)."""
    return {**(data or {}), "shape": list(shape), "spacing_um": list(spacing),
            "missing_fraction": float((~measured).mean()), "points_used": int(measured.sum())}
