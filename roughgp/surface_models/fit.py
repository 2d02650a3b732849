r"""Fit a model of the ladder to a measured surface or profile and keep it as a
:class:`~roughgp.surface_models.model.FittedModel`.

* :func:`fit_surface_model`: the F-operator on the measured heights, then eq 18 (or its Matérn
  variant) plus white noise (eq 8) on the measured points alone by block composite likelihood
  (:func:`roughgp.inference.block_fit.fit_ground_to_valid_points`) or, with
  ``likelihood="whittle"``, by the debiased spatial Whittle likelihood of every measured point
  (:func:`roughgp.inference.whittle_fit.fit_whittle`): holes are allowed.
* :func:`fit_profile_model`: the F-operator (a line) on a profile, then the spectral mixture
  of eq 21 by the procedure of section 3.3
  (:func:`roughgp.inference.fitting.fit_spectral_mixture`).
* :func:`fit_sm_model`: the 2-D spectral mixture by the Whittle likelihood
  (:mod:`roughgp.surface_models.spectral_mixture` says how).
* :func:`fit_psd_model`: the measured PSD itself, smoothed
  (:mod:`roughgp.surface_models.measured_psd`).

**Like with like.** The S- and L-filters asked for
(:func:`roughgp.metrology.filters.surface_texture`) are not applied before the fit: the model
describes the heights after F (stage ``"form-removed"``), and
:func:`~roughgp.surface_models.chain.rest_of_chain` puts its simulations through the holes, the
F-operator and the filters exactly as the measurement went, before
:func:`roughgp.checking.model_check.check_model` compares them. The other route, fitting the
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
the model, and its simulations reproduce them (:mod:`roughgp.surface_models.model`).
"""

from __future__ import annotations

import dataclasses
import math
import time
import warnings

import numpy as np

from roughgp.common.checks import surface_array
from roughgp.common.grid import normalize
from roughgp.inference.block_fit import BlockFit, fit_ground_to_valid_points
from roughgp.inference.whittle_fit import WhittleFit, fit_whittle
from roughgp.inference.fitting import MIN_POINTS, SpectralMixtureFit, fit_spectral_mixture
from roughgp.metrology.filters import Texture
from roughgp.surface_models import psd_core, psd_table
from roughgp.surface_models.chain import (
    described_data,
    form_removed_surface,
    marginal_of,
    measured_chain,
)
from roughgp.surface_models.in_range import keep_in_range
from roughgp.surface_models.model import FittedModel
from roughgp.surface_models.order_scores import with_order_scores
from roughgp.surface_models.spectral_mixture import MAX_COMPONENTS, whittle_fit

__all__ = ["LIKELIHOODS", "SurfaceModelFit", "ProfileModelFit", "SmModelFit", "PsdModelFit",
           "fit_surface_model", "fit_profile_model", "fit_sm_model", "fit_psd_model"]

#: the likelihoods of eq 18's fit: a few blocks (the default), or every point (Whittle)
LIKELIHOODS = ("blocks", "whittle")


@dataclasses.dataclass(frozen=True)
class SurfaceModelFit:
    """What :func:`fit_surface_model` returns: the model, the measurement's chain
    (``texture``), the fit (a :class:`~roughgp.inference.block_fit.BlockFit` or a
    :class:`~roughgp.inference.whittle_fit.WhittleFit`), and what
    :func:`~roughgp.surface_models.in_range.keep_in_range` found out of range and did
    (``range_notes``)."""

    model: FittedModel
    texture: Texture
    block_fit: BlockFit | WhittleFit
    range_notes: tuple = ()


@dataclasses.dataclass(frozen=True)
class ProfileModelFit:
    """What :func:`fit_profile_model` returns: the model, the filtered profile and the fit."""

    model: FittedModel
    texture: Texture
    mixture: SpectralMixtureFit


def _marginal(heights, non_gaussian, marginal, texture=None, l_um=None):
    if marginal is None:
        marginal = "johnson" if non_gaussian else "gaussian"
    return marginal_of(heights, marginal, None if texture is None else texture.sl, l_um)


def fit_surface_model(z, spacing=1.0, *, form="plane", s=None, l=None, degree=2, axis="auto",
                      block=24, n_blocks=12, seed=0, non_gaussian=False, nu=0.5,
                      data=None, stage="form-removed", marginal=None,
                      likelihood="blocks", device=None) -> SurfaceModelFit:
    """Fit eq 18 plus noise to a measured surface ``z[iy, ix]`` (um, NaN where unmeasured).

    Args:
        spacing: scalar or ``(dy, dx)``, um.
        form, degree, axis: the F-operator (``"plane"``, ``"polynomial"``, ``"cylinder"`` or
            None; :func:`roughgp.metrology.form.remove_form`).
        s, l: S- and L-filter nesting indices in um, ``"auto"`` or None (default: off).
        block, n_blocks, seed: the block composite likelihood's blocks
            (:func:`~roughgp.inference.block_fit.fit_ground_to_valid_points`).
        likelihood: ``"blocks"`` (the block composite likelihood, the default) or
            ``"whittle"`` (the debiased spatial Whittle likelihood of every measured point,
            :func:`~roughgp.inference.whittle_fit.fit_whittle`: its precision grows with the
            map; ``block`` and ``n_blocks`` are then not used).
        device: with ``likelihood="whittle"``, where its FFTs and gradient run (None: torch on
            the CPU; ``"cuda"``: a GPU, :mod:`roughgp.common.device`); the block fit has no
            device path and refuses one.
        non_gaussian: keep the fitted heights' skewness and kurtosis in the model (the same as
            ``marginal="johnson"``).
        marginal: ``"gaussian"``, ``"johnson"`` or ``"iaaft"`` (the heights' quantile function,
            matched exactly by :mod:`roughgp.surface_models.iaaft`); overrides
            ``non_gaussian``.
        nu: 0.5 (eq 18, the default), or 1.5 / 2.5 for eq 18's anisotropy with a smoother
            Matérn profile (model ``"eq18-matern"``).
        data: a dict describing the source (file name, checksum, ...), kept in the model.
        stage: ``"form-removed"`` (default: the model describes the heights after F, and its
            simulations go through S and L as the measurement did) or ``"filtered"`` (fitted
            to the heights after S and L; module docstring).
    """
    arr = surface_array(z)
    _, (dy, dx) = normalize(arr.shape, spacing)
    start = time.perf_counter()
    texture, cutoffs, heights = measured_chain(arr, (dy, dx), form, s, l, degree, axis, stage)
    if likelihood not in LIKELIHOODS:
        raise ValueError(f"likelihood must be one of {', '.join(LIKELIHOODS)}, got "
                         f"{likelihood!r}")
    if device is not None and likelihood != "whittle":
        raise ValueError(f"device={device!r} applies to likelihood='whittle' only (the block "
                         f"fit runs on the CPU); leave device out or use likelihood='whittle'")
    if likelihood == "whittle":
        fit = fit_whittle(heights, spacing=(dy, dx), nu=nu, device=device)
        how = {"method": "maximum debiased spatial Whittle likelihood of every measured point "
                         "(roughgp.inference.whittle_fit)", "likelihood": "whittle",
               "log_likelihood": fit.log_likelihood, "n_frequencies": fit.n_frequencies}
    else:
        fit = fit_ground_to_valid_points(heights, spacing=(dy, dx), block=block,
                                         n_blocks=n_blocks, seed=seed, nu=nu)
        how = {"method": "maximum block composite likelihood (roughgp.inference.block_fit)",
               "log_likelihood": fit.log_likelihood, "block": block,
               "n_blocks": len(fit.blocks)}
    g = fit.groove
    hyper = {"variance_um2": g.variance, "lambda_a_um": g.lengthscales[0],
             "lambda_b_um": g.lengthscales[1], "angle_deg": math.degrees(g.angle),
             "noise_variance_um2": fit.noise_variance, "mean_um": fit.mean}
    if nu != 0.5:
        hyper["nu"] = float(nu)
    missing = ~np.isfinite(heights)
    described = {**(data or {}), "shape": list(arr.shape), "spacing_um": [dy, dx],
                 "missing_fraction": float(missing.mean()), "points_used": fit.n_points}
    how.update(seed=seed, seconds=round(time.perf_counter() - start, 2))
    model = FittedModel("eq18" if nu == 0.5 else "eq18-matern", hyper, (dy, dx),
                        _marginal(heights, non_gaussian, marginal,
                                  texture if stage == "form-removed" else None,
                                  cutoffs["l_um"]), tuple(texture.operators),
                        cutoffs, described, how, stage)
    model, notes = keep_in_range(model, arr.shape, block if likelihood == "blocks" else None)
    model = with_order_scores(model, arr, (dy, dx), seed=seed)
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


@dataclasses.dataclass(frozen=True)
class SmModelFit:
    """What :func:`fit_sm_model` returns: the model, the measurement's chain (``texture``),
    the BIC table ``(Q, Whittle log likelihood, BIC)`` (of the fits, before the weights are
    apportioned) and the values on a bound."""

    model: FittedModel
    texture: Texture
    table: tuple
    range_notes: tuple = ()


def fit_sm_model(z, spacing=1.0, *, form="plane", s=None, l=None, degree=2, axis="auto",
                 marginal="gaussian", seed=0, data=None,
                 max_components=MAX_COMPONENTS) -> SmModelFit:
    """The 2-D spectral mixture (``"sm2d"``) of a surface ``z[iy, ix]`` (um, NaN where
    unmeasured; :mod:`roughgp.surface_models.spectral_mixture` says how), of stage
    ``"form-removed"``.

    Args:
        spacing: scalar or ``(dy, dx)``, um.
        form, degree, axis, s, l: the operator chain, as in
            :func:`~roughgp.surface_models.fit.fit_surface_model`.
        marginal: ``"gaussian"``, ``"johnson"`` or ``"iaaft"``
            (:func:`~roughgp.surface_models.chain.marginal_of`).
        seed: kept in the model (the fit draws nothing).
        max_components: the largest Q tried, 1 to 8 (default :data:`MAX_COMPONENTS`).
    """
    start = time.perf_counter()
    arr, (dy, dx), texture, cutoffs, heights = form_removed_surface(
        z, spacing, form, s, l, degree, axis, marginal, name="sm", min_side=16)
    measured = np.isfinite(heights)
    mixture, table, notes = whittle_fit(heights, (dy, dx), max_components)
    hyper = {**mixture.hyperparameters(), "mean_um": float(np.mean(heights[measured]))}
    described = described_data(data, arr.shape, (dy, dx), measured)
    how = {"method": ("maximum Whittle likelihood on the prewhitened Tukey-windowed periodogram "
                      "of the form-removed heights; Q by BIC, weights apportioned to the "
                      "periodogram's power (roughgp.surface_models.spectral_mixture)"),
           "log_likelihood": next(ll for q, ll, _ in table if q == mixture.size),
           "bic": [[q, round(b, 2)] for q, _, b in table], "seed": seed,
           "seconds": round(time.perf_counter() - start, 2)}
    if notes:
        how["range_notes"] = list(notes)
    model = FittedModel("sm2d", hyper, (dy, dx),
                        marginal_of(heights, marginal, texture.sl, cutoffs["l_um"]),
                        tuple(texture.operators), cutoffs, described, how, "form-removed")
    model = with_order_scores(model, arr, (dy, dx), seed=seed)
    return SmModelFit(model, texture, tuple(table), tuple(notes))


@dataclasses.dataclass(frozen=True)
class PsdModelFit:
    """What :func:`fit_psd_model` returns: the model, the measurement's chain (``texture``) and
    the measured heights' variance the table was scaled to (um^2)."""

    model: FittedModel
    texture: Texture
    variance: float
    range_notes: tuple = ()


def fit_psd_model(z, spacing=1.0, *, form="plane", s=None, l=None, degree=2, axis="auto",
                  marginal="gaussian", seed=0, data=None) -> PsdModelFit:
    """The measured-psd model of a surface ``z[iy, ix]`` (um, NaN where unmeasured;
    :mod:`roughgp.surface_models.measured_psd` says how).

    Args:
        spacing: scalar or ``(dy, dx)``, um.
        form, degree, axis, s, l: the operator chain, as in
            :func:`~roughgp.surface_models.fit.fit_surface_model` (the model describes the
            heights after F; S and L are applied to its simulations as to the measurement).
        marginal: ``"gaussian"``, ``"johnson"`` (the heights' skewness and kurtosis; drawn by
            IAAFT toward the Johnson distribution, which keeps the PSD) or ``"iaaft"`` (their
            quantile function, :mod:`roughgp.surface_models.iaaft`).
        seed: kept in the model (the estimate itself draws nothing).
        data: a dict describing the source, kept in the model.
    """
    start = time.perf_counter()
    arr, (dy, dx), texture, cutoffs, heights = form_removed_surface(
        z, spacing, form, s, l, degree, axis, marginal, name="measured-psd", min_side=8)
    measured = np.isfinite(heights)
    table, f_min, f_max, core = psd_table.low_frequency_core(heights, (dy, dx))
    variance = float(np.var(heights[measured]))
    table *= variance / psd_table.table_variance(table, f_min, f_max, (dy, dx), arr.shape,
                                                 core=core)
    if cutoffs["s_um"] is not None or cutoffs["l_um"] is not None:
        band = texture.sl[np.isfinite(texture.sl)]
        table = psd_table.scale_to_band(table, f_min, f_max, (dy, dx), arr.shape, variance,
                                        float(np.var(band)), cutoffs["s_um"], cutoffs["l_um"],
                                        core=core)
    hyper = {"psd_um4": table.tolist(), "frequency_min_per_um": f_min,
             "frequency_max_per_um": f_max, "noise_variance_um2": 0.0,
             "mean_um": float(np.mean(heights[measured])), **psd_core.to_hyperparameters(core)}
    described = described_data(data, arr.shape, (dy, dx), measured)
    how = {"method": (f"Tukey-windowed periodogram of the mean-filled form-removed heights, "
                      f"{psd_table.N_RADII} x {psd_table.N_ANGLES} log-polar bins of >= "
                      f"{psd_table.MIN_ORDINATES} ordinates brought to the bins' centres along "
                      f"the local slope, the ordinates within {psd_core.CORE_STEPS} frequency "
                      f"steps kept as measured, scaled to the variance and the filtered band's "
                      f"(roughgp.surface_models.psd_table, psd_core)"),
           "seed": seed, "seconds": round(time.perf_counter() - start, 2)}
    model = FittedModel("measured-psd", hyper, (dy, dx), marginal_of(heights, marginal, texture.sl,
                                                           cutoffs["l_um"]),
                        tuple(texture.operators),
                        cutoffs, described, how, "form-removed")
    model = with_order_scores(model, arr, (dy, dx), seed=seed)
    return PsdModelFit(model, texture, variance)
