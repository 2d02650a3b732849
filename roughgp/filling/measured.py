"""A measured surface with unmeasured (NaN) points, filled end to end (beyond the paper).

The pipeline of ``roughgp fill``, as one call: remove the form (the F-operator,
:func:`roughgp.metrology.form.remove_form`: a least-squares plane by default, a cylinder for a
curved part), fit eq 18 plus white noise (eq 8) on the measured points alone
(:func:`roughgp.inference.block_fit.fit_ground_to_valid_points`) or take the hyperparameters of
a fitted model (:class:`~roughgp.surface_models.model.FittedModel`), fill the missing points
with the GP posterior mean and sd of the form-removed surface, and add the form back, so that
the filled map is in the measurement's own heights. The fill works on the form-removed heights
only: a model fitted after S- or L-filters describes filtered heights, so its filters are not
applied here (the fill is of the measurement, not of its roughness).

Two solvers: ``method="local"`` (the default) is moving-window kriging
(:func:`roughgp.filling.local_fill.fill_gaps_locally`): bounded work, an exact sd for each
window, no circulant embedding; it holds on real measurements, whose fitted correlation
lengths may exceed the field and whose noise may be near zero. ``method="global"`` conditions on
all measured points (:func:`roughgp.filling.global_fill.fill_gaps`: conjugate gradients and
pathwise draws for the sd), best for synthetic, well-conditioned cases; its CG may not
converge on such measurements (``gaps.converged`` says so).

``self_check=True`` holds out 2 % of the measured points first (at most 5000), fits
without them, fills them and compares with their heights and with linear interpolation
(:mod:`roughgp.filling.self_check`): it says whether the fill beats linear
interpolation on this file. The band is then calibrated on held-out copies of the map's own
holes, one factor per size of hole and depth in it (:mod:`roughgp.filling.hole_band`,
:attr:`MeasuredFill.band`).
``nu="auto"`` does that for each of ``NU_CHOICES`` and keeps the smoothness that fills the
held-out points best (eq 18 unless another is clearly better:
:func:`~roughgp.filling.self_check.choose_nu`). The fill itself then uses all
measured points.
"""

from __future__ import annotations

import dataclasses
import functools

import numpy as np

from roughgp.common.checks import boolean_map, surface_array
from roughgp.common.grid import normalize
from roughgp.filling.global_fill import GapFill, fill_gaps
from roughgp.filling.hole_band import HoleBand, calibrate_hole_band
from roughgp.filling.local_fill import LocalFill, fill_gaps_locally
from roughgp.filling.mark_trace import PERIODIC_EQUATIONS, map_trace, roughness_kernel
from roughgp.filling.self_check import (
    CHECK_SHARE,
    GAUSSIAN_FACTOR,
    MIN_CHECK_POINTS,
    NU_CHOICES,
    FillSelfCheck,
    choose_nu,
    held_out_points,
    predictive_sd,
    self_check_fill,
)
from roughgp.inference.block_fit import BlockFit, fit_ground_to_valid_points
from roughgp.metrology.form import FormFit, form_heights, remove_form

__all__ = ["MeasuredFill", "fill_measured_surface"]


@dataclasses.dataclass
class MeasuredFill:
    """What :func:`fill_measured_surface` returns.

    Attributes:
        filled: the measured heights, with the missing ones filled by the posterior mean plus
            the removed form (the measurement's own heights).
        sd: posterior sd of the latent surface at the filled points, 0 at measured ones
            (and everywhere without draws).
        missing: boolean map of the filled points.
        form: the F-operator's fit removed before the fill and added back.
        fit: the eq 18 fit on the measured points (None when a model was given).
        kernel, noise_variance: what the fill used.
        gaps: the fill of the form-removed surface: a
            :class:`~roughgp.filling.local_fill.LocalFill` (``method="local"``) or a
            :class:`~roughgp.filling.global_fill.GapFill` (``"global"``).
        method: ``"local"`` or ``"global"``.
        nu: the smoothness of the kernel used (the fitted or the model's).
        self_checks: ``{nu: FillSelfCheck}`` of the smoothness values checked (empty without
            a self-check); self_check: that of ``nu`` (None without).
        hole_band: the band's factor per size of hole and depth in it
            (:mod:`roughgp.filling.hole_band`), calibrated with the self-check (None without).
    """

    filled: np.ndarray
    sd: np.ndarray
    missing: np.ndarray
    form: FormFit
    fit: BlockFit | None
    kernel: object
    noise_variance: float
    gaps: LocalFill | GapFill
    method: str = "local"
    nu: float = 0.5
    self_checks: dict = dataclasses.field(default_factory=dict)
    hole_band: HoleBand | None = None

    @property
    def self_check(self) -> FillSelfCheck | None:
        return self.self_checks.get(self.nu)

    @property
    def band_factor(self) -> float:
        """:math:`k` of the 95 % band ``+- k sqrt(sd^2 + sigma^2)`` of a new measurement at a
        filled point as the self-check's small discs calibrate it, else Gaussian (1.96). The
        band itself (:attr:`band`) takes its factor from the size of each hole and the depth
        in it where the self-check ran (:attr:`band_factors`)."""
        return GAUSSIAN_FACTOR if self.self_check is None else self.self_check.band_factor

    @functools.cached_property
    def band_factors(self) -> np.ndarray:
        """The band's factor at each filled point (0 at measured ones): by the size of its hole
        and its depth in it (:attr:`hole_band`) where the self-check ran, else
        :attr:`band_factor` (computed once: the holes' depths are a distance transform of the
        map)."""
        if self.hole_band is None:
            return np.where(self.missing, self.band_factor, 0.0)
        return self.hole_band.factor_map(self.missing)

    @property
    def predictive_sd(self) -> np.ndarray:
        """The sd of a new measurement at the filled points, ``sqrt(sd^2 + sigma^2)`` (0 at
        measured ones)."""
        return np.where(self.missing, predictive_sd(self.sd, self.noise_variance), 0.0)

    @property
    def band(self) -> np.ndarray:
        """The half-width of that band at the filled points (0 at measured ones)."""
        return self.band_factors * self.predictive_sd


def fill_measured_surface(z, *, spacing=1.0, n_samples=16, seed=None, block=24, n_blocks=12,
                          form="plane", degree=2, axis="auto", model=None,
                          mask=None, method="local", tile=16, margin=6, nu=0.5,
                          self_check=False, device=None, progress=None) -> MeasuredFill:
    """Remove the form, fit eq 18 on the measured points (or use ``model``), fill the NaN
    (and ``mask``-ed) points, add the form back.

    Args:
        z: height map ``z[iy, ix]`` with NaN where not measured.
        spacing: scalar or ``(dy, dx)``.
        n_samples: ``method="global"``: pathwise draws for the sd (0: the mean only, far
            quicker); the local sd is exact and needs none.
        seed: int or None: the fit's blocks and the draws.
        block, n_blocks: the fit's blocks
            (:func:`~roughgp.inference.block_fit.fit_ground_to_valid_points`).
        form, degree, axis: the F-operator (:func:`~roughgp.metrology.form.remove_form`).
        model: a :class:`~roughgp.surface_models.model.FittedModel` of a surface (eq 18 or
            its Matérn variant; a periodic-mark model fills what the map's own marks leave,
            :mod:`roughgp.filling.mark_trace`) whose kernel and noise are used instead of a
            fit (through its
            ``kind``, ``kernel()``, ``noise_variance``, ``hyperparameters`` and ``equation``:
            this package sits below the models).
        nu: the smoothness of the fit when no model is given (0.5: eq 18; 1.5, 2.5: Matérn;
            ``"auto"``: the self-check's choice among ``NU_CHOICES``).
        self_check: hold out measured points first and check the fill on them (module
            docstring); implied by ``nu="auto"``. It uses the local solver whatever ``method``.
        mask: optional boolean map: measured points to treat as missing as well (e.g. to hide
            them for a cross-validation).
        method: ``"local"`` (moving-window kriging, ``tile`` and ``margin`` in points) or
            ``"global"`` (module docstring).
        device: ``"global"`` only: None (numpy) or a torch device (:mod:`roughgp.common.device`).
        progress: ``"local"`` only: a callback ``(done, total)`` after each window of the fill.
    """
    z = surface_array(z)
    missing = np.isnan(z)
    if mask is not None:
        mask = boolean_map(mask, z.shape)
        missing = missing | mask
    if not missing.any():
        raise ValueError("z has no missing (NaN) point: nothing to fill")
    if method not in ("local", "global"):
        raise ValueError(f"method must be 'local' or 'global', got {method!r}")
    if model is not None and (getattr(model, "kind", None) != "surface"
                              or not callable(getattr(model, "kernel", None))):
        raise ValueError("model must be a FittedModel of a surface")
    if nu != "auto" and nu not in NU_CHOICES:
        raise ValueError(f"nu must be one of {NU_CHOICES} or 'auto', got {nu!r}")
    if nu == "auto" and model is not None:
        raise ValueError("nu='auto' chooses the smoothness of a fit; a model has its own")
    _, (dy, dx) = normalize(z.shape, spacing)
    residual, form_fit = remove_form(np.where(missing, np.nan, z), (dy, dx), form,
                                     degree=degree, axis=axis)
    measured = np.isfinite(residual)
    held_out = held_out_points(measured, seed) if (self_check or nu == "auto") else None
    if nu == "auto" and held_out is None:
        raise ValueError(f"nu='auto' needs a self-check, and {int(measured.sum())} measured "
                         f"points are too few to hold some out (at least "
                         f"{MIN_CHECK_POINTS / CHECK_SHARE:.0f} are needed)")
    fit, checks, trace = None, {}, 0.0
    if model is None:
        fits = {}
        for smoothness in (NU_CHOICES if nu == "auto" else (nu,)):
            # nu="auto": eq 18's optimum joins the Matern fits' starts (two optimisations each)
            fits[smoothness] = fit_ground_to_valid_points(
                residual, spacing=(dy, dx), mask=held_out, block=block, n_blocks=n_blocks,
                seed=seed, nu=smoothness, start=fits.get(0.5) if smoothness != 0.5 else None)
            if held_out is not None:
                checks[smoothness] = self_check_fill(
                    residual, fits[smoothness].kernel,
                    noise_variance=fits[smoothness].noise_variance, spacing=(dy, dx),
                    held_out=held_out, nu=smoothness, margin=margin)
        nu = choose_nu(checks) if nu == "auto" else nu
        fit = fits[nu]
        kernel, noise_variance = fit.kernel, fit.noise_variance
    else:
        if model.equation in PERIODIC_EQUATIONS:   # krige what the map's own marks leave
            trace = map_trace(residual, model, (dy, dx))
            residual = residual - trace
            kernel = roughness_kernel(model)
        else:
            kernel = model.kernel()
        noise_variance = model.noise_variance
        nu = float(model.hyperparameters.get("nu", 0.5))
        if held_out is not None:
            checks[nu] = self_check_fill(residual, kernel, noise_variance=noise_variance,
                                         spacing=(dy, dx), held_out=held_out, nu=nu,
                                         margin=margin,
                                         kernel_name=f"the model's {model.equation}")
    hole_band = None
    if held_out is not None:
        hole_band = calibrate_hole_band(residual, kernel, noise_variance=noise_variance,
                                        spacing=(dy, dx), seed=seed, tile=tile,
                                        margin=margin)
    if method == "local":
        gaps = fill_gaps_locally(residual, kernel, noise_variance=noise_variance,
                                 spacing=(dy, dx), mask=mask, tile=tile, margin=margin,
                                 progress=progress)
    else:
        gaps = fill_gaps(residual, kernel, noise_variance=noise_variance, spacing=(dy, dx),
                         mask=mask, n_samples=n_samples, seed=seed, device=device)
    form_part = form_heights(form_fit, z.shape, (dy, dx)) + trace
    filled = np.where(missing, gaps.mean + form_part, z)
    sd = np.where(missing, gaps.sd, 0.0)
    return MeasuredFill(filled=filled, sd=sd, missing=missing, form=form_fit, fit=fit,
                        kernel=kernel, noise_variance=float(noise_variance), gaps=gaps,
                        method=method, nu=float(nu), self_checks=checks, hole_band=hole_band)
