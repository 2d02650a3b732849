r"""Fit a model to a measured surface or profile and keep it as a :class:`FittedModel`.

* :func:`fit_surface_model`: the F-operator on the measured heights, then eq 18 plus white
  noise (eq 8) on the measured points alone by block composite likelihood
  (:func:`roughgp.inference.block_fit.fit_ground_to_valid_points`): holes are allowed.
* :func:`fit_profile_model`: the F-operator (a line) on a profile, then the spectral mixture
  of eq 21 by the procedure of section 3.3
  (:func:`roughgp.inference.fitting.fit_spectral_mixture`).

**Like with like.** The S- and L-filters asked for
(:func:`roughgp.metrology.filters.surface_texture`) are not applied before the fit: the model describes the heights after F (stage
``"form-removed"``), and :func:`rest_of_chain` puts its simulations through the holes, the
F-operator and the filters exactly as the measurement went, before
:func:`roughgp.beyond.measured.check.check_model` compares them. The other route, fitting the
filtered heights with the filtered covariance :math:`S(f)\,|1 - H_L(f)|^2\,|H_S(f)|^2` (the ISO
Gaussian filter's transmission is closed-form), needs an ACVF without closed form in the block
likelihood and describes an infinite field; the route taken applies the same code, edges,
NaN-aware weights and form fit included, to both sides. Fitting a stationary eq 18 to the
filtered heights and comparing its unfiltered draws (stage ``"filtered"``, version 1's route)
is measured against it on six seeded eq 18 surfaces (128 x 128, :math:`\lambda = (8, 3)`,
L-filter 25, three with a 20 x 30 hole; 19 simulations each): ``"filtered"`` put 2.8 of 13
parameters outside on average (Sal on 6 of 6, Str on 5 of 6: the fitted lengths fall to about
half the true ones, 4.3 and 1.6 for 8 and 3, to mimic the filter's negative lobe),
``"form-removed"`` 1.0 (Sal and Str once each; the fitted lengths within 20 % of the truth).
``stage="filtered"`` stays available for that comparison.

By default no S-filter is applied: the model's white noise (eq 8) stands for the instrument's
small-scale noise, which an S-filter would smooth into a correlated signal. With
``non_gaussian=True`` the skewness and kurtosis of the heights at the model's stage are kept in
the model, and its simulations reproduce them (:mod:`roughgp.beyond.measured.model`).
"""

from __future__ import annotations

import dataclasses
import math
import time
import warnings

import numpy as np

from roughgp.beyond.measured.in_range import keep_in_range
from roughgp.beyond.measured.model import STAGES, FittedModel
from roughgp.common.grid import normalize
from roughgp.inference.block_fit import BlockFit, fit_ground_to_valid_points
from roughgp.inference.fitting import MIN_POINTS, SpectralMixtureFit, fit_spectral_mixture
from roughgp.metrology.filters import Texture, surface_texture

__all__ = ["MARGINALS", "marginal_of", "SurfaceModelFit", "ProfileModelFit", "fit_surface_model",
           "fit_profile_model",
           "apply_operators", "rest_of_chain", "form_removed", "measured_chain",
           "form_removed_surface", "described_data"]


@dataclasses.dataclass(frozen=True)
class SurfaceModelFit:
    """What :func:`fit_surface_model` returns: the model, the measurement's chain
    (``texture``), the block fit, and what :func:`~roughgp.beyond.measured.in_range.keep_in_range`
    found out of range and did (``range_notes``)."""

    model: FittedModel
    texture: Texture
    block_fit: BlockFit
    range_notes: tuple = ()


@dataclasses.dataclass(frozen=True)
class ProfileModelFit:
    """What :func:`fit_profile_model` returns: the model, the filtered profile and the fit."""

    model: FittedModel
    texture: Texture
    mixture: SpectralMixtureFit


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
    ``"iaaft"`` (:mod:`roughgp.beyond.measured.iaaft`); with an L-filter (``l_um``) the IAAFT
    marginal is that of the ``filtered`` heights, matched in the band the filter passes
    (``above_l_um``)."""
    if method not in MARGINALS:
        raise ValueError(f"marginal must be one of {list(MARGINALS)}, got {method!r}")
    if method == "gaussian":
        return None
    if method == "iaaft":
        from roughgp.beyond.measured import iaaft
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


def _marginal(heights, non_gaussian, marginal, texture=None, l_um=None):
    if marginal is None:
        marginal = "johnson" if non_gaussian else "gaussian"
    return marginal_of(heights, marginal, None if texture is None else texture.sl, l_um)


def _cutoffs(form, s, l, degree, axis):
    return {"form": form, "s_um": s, "l_um": l, "degree": degree, "axis": axis}


def measured_chain(arr, spacing, form, s, l, degree, axis, stage):
    """The measurement's chain (its cut-offs resolved), and the heights the model of ``stage``
    is fitted to: after F alone (``"form-removed"``) or after every operator."""
    if stage not in STAGES:
        raise ValueError(f"stage must be one of {list(STAGES)}, got {stage!r}")
    texture = surface_texture(arr, spacing, form=form, s=s, l=l, degree=degree, axis=axis)
    cutoffs = _cutoffs(form, texture.cutoffs.s, texture.cutoffs.l, degree, axis)
    heights = texture.sl if stage == "filtered" else form_removed(arr, spacing, cutoffs).sl
    return texture, cutoffs, heights


def form_removed_surface(z, spacing, form, s, l, degree, axis, marginal, *, name, min_side):
    """``(arr, (dy, dx), texture, cutoffs, heights)``: the checks shared by the models fitted to
    a surface's form-removed heights (``marginal`` one of :data:`MARGINALS`, ``z`` a surface of
    at least ``min_side`` points a side: a ``ValueError`` naming the model ``name``
    otherwise), then :func:`measured_chain` of stage ``"form-removed"``."""
    if marginal not in MARGINALS:
        raise ValueError(f"marginal must be one of {list(MARGINALS)}, got {marginal!r}")
    arr = np.asarray(z, dtype=np.float64)
    if arr.ndim != 2:
        raise ValueError(f"z must be a surface z[iy, ix], got shape {arr.shape}")
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


def fit_surface_model(z, spacing=1.0, *, form="plane", s=None, l=None, degree=2, axis="auto",
                      block=24, n_blocks=12, seed=0, non_gaussian=False, nu=0.5,
                      data=None, stage="form-removed", marginal=None) -> SurfaceModelFit:
    """Fit eq 18 plus noise to a measured surface ``z[iy, ix]`` (um, NaN where unmeasured).

    Args:
        spacing: scalar or ``(dy, dx)``, um.
        form, degree, axis: the F-operator (``"plane"``, ``"polynomial"``, ``"cylinder"`` or
            None; :func:`roughgp.metrology.form.remove_form`).
        s, l: S- and L-filter nesting indices in um, ``"auto"`` or None (default: off).
        block, n_blocks, seed: the block composite likelihood's blocks
            (:func:`~roughgp.inference.block_fit.fit_ground_to_valid_points`).
        non_gaussian: keep the fitted heights' skewness and kurtosis in the model (the same as
            ``marginal="johnson"``).
        marginal: ``"gaussian"``, ``"johnson"`` or ``"iaaft"`` (the heights' quantile function,
            matched exactly by :mod:`roughgp.beyond.measured.iaaft`); overrides
            ``non_gaussian``.
        nu: 0.5 (eq 18, the default), or 1.5 / 2.5 for eq 18's anisotropy with a smoother
            Matérn profile (model ``"eq18-matern"``).
        data: a dict describing the source (file name, checksum, ...), kept in the model.
        stage: ``"form-removed"`` (default: the model describes the heights after F, and its
            simulations go through S and L as the measurement did) or ``"filtered"`` (fitted
            to the heights after S and L; module docstring).
    """
    arr = np.asarray(z, dtype=np.float64)
    if arr.ndim != 2:
        raise ValueError(f"z must be a surface z[iy, ix], got shape {arr.shape}")
    _, (dy, dx) = normalize(arr.shape, spacing)
    start = time.perf_counter()
    texture, cutoffs, heights = measured_chain(arr, (dy, dx), form, s, l, degree, axis, stage)
    fit = fit_ground_to_valid_points(heights, spacing=(dy, dx), block=block, n_blocks=n_blocks,
                                     seed=seed, nu=nu)
    g = fit.groove
    hyper = {"variance_um2": g.variance, "lambda_a_um": g.lengthscales[0],
             "lambda_b_um": g.lengthscales[1], "angle_deg": math.degrees(g.angle),
             "noise_variance_um2": fit.noise_variance, "mean_um": fit.mean}
    if nu != 0.5:
        hyper["nu"] = float(nu)
    missing = ~np.isfinite(heights)
    described = {**(data or {}), "shape": list(arr.shape), "spacing_um": [dy, dx],
                 "missing_fraction": float(missing.mean()), "points_used": fit.n_points}
    how = {"method": "maximum block composite likelihood (roughgp.inference.block_fit)",
           "log_likelihood": fit.log_likelihood, "block": block, "n_blocks": len(fit.blocks),
           "seed": seed, "seconds": round(time.perf_counter() - start, 2)}
    model = FittedModel("eq18" if nu == 0.5 else "eq18-matern", hyper, (dy, dx),
                        _marginal(heights, non_gaussian, marginal,
                                  texture if stage == "form-removed" else None,
                                  cutoffs["l_um"]), tuple(texture.operators),
                        cutoffs, described, how, stage)
    model, notes = keep_in_range(model, arr.shape, block)
    return SurfaceModelFit(model, texture, fit, tuple(notes))


def fit_profile_model(z, spacing=1.0, *, form="plane", s=None, l=None, num_mixtures=5, seed=0,
                      n_candidates=10, non_gaussian=False, data=None,
                      stage="form-removed") -> ProfileModelFit:
    """Fit eq 21 plus noise to a measured profile ``z[ix]`` (um; complete, no NaN).

    Args: as :func:`fit_surface_model`; ``form="plane"`` is the least-squares line;
    ``num_mixtures`` (Q) and ``n_candidates`` as in
    :func:`~roughgp.inference.fitting.fit_spectral_mixture`.
    """
    arr = np.asarray(z, dtype=np.float64)
    if arr.ndim != 1:
        raise ValueError(f"z must be a profile z[ix], got shape {arr.shape}")
    dx = float(np.ravel(spacing)[-1])
    if not (math.isfinite(dx) and dx > 0):
        raise ValueError(f"spacing must be > 0, got {spacing!r}")
    missing = int(np.count_nonzero(~np.isfinite(arr)))
    if missing:
        raise ValueError(f"the profile has {missing} missing (NaN) point(s); the eq 21 fit "
                         "needs a complete profile (fill or crop them first)")
    if arr.size < MIN_POINTS:
        raise ValueError(f"the profile has {arr.size} points; the fit needs at least "
                         f"{MIN_POINTS}")
    start = time.perf_counter()
    texture, cutoffs, heights = measured_chain(arr, dx, form, s, l, 2, "auto", stage)
    x = np.arange(arr.size) * dx
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        mix = fit_spectral_mixture(x, heights, num_mixtures, seed=seed,
                                   n_candidates=n_candidates,
                                   n_optimise=min(3, n_candidates))
    hyper = {"weights_um2": mix.weights, "frequencies_per_um": mix.means,
             "spectral_variances_per_um2": mix.variances,
             "noise_variance_um2": mix.noise_variance, "mean_um": mix.mean}
    described = {**(data or {}), "shape": [arr.size], "spacing_um": [dx],
                 "missing_fraction": 0.0, "points_used": int(arr.size)}
    how = {"method": "maximum marginal likelihood, section 3.3 (roughgp.inference.fitting)",
           "log_likelihood": mix.log_marginal_likelihood, "seed": seed,
           "n_candidates": n_candidates, "seconds": round(time.perf_counter() - start, 2)}
    model = FittedModel("eq21", hyper, (dx,), _marginal(heights, non_gaussian, None),
                        tuple(texture.operators), cutoffs, described, how, stage)
    return ProfileModelFit(model, texture, mix)
