r"""A fitted model of a measured surface or profile, as a versioned JSON file (beyond the paper).

The paper's loop is: measure a surface, fit the GP, simulate new surfaces like it. A
:class:`FittedModel` is the middle of that loop, kept: the equation, its hyperparameters with
their units, the height distribution (Gaussian, eq 8, or a Johnson transform of prescribed
skewness and kurtosis, :mod:`roughgp.non_gaussian`), the operators applied to the data
before the fit (form removal, S- and L-filters), the data it was fitted on and the fit's log
likelihood. ``save`` / ``load`` write and read it (``format: roughgp-model``, ``version: 2``;
a file of version 1 is read as stage ``"filtered"``, what version 1 fitted; the schema is
:mod:`roughgp.surface_models.schema`); ``simulate(shape, seed=...)`` draws new surfaces from
it.

The stage of the operator chain (form removal F, then the S- and L-filters) at which the model
describes the surface is ``stage``:

* ``"form-removed"`` (what :func:`~roughgp.surface_models.fit.fit_surface_model` fits): the
  heights after F, before S and L. A simulation is put through the rest of the chain (F again,
  S, L, with the measurement's holes) before it is compared with the measurement
  (:func:`roughgp.surface_models.chain.rest_of_chain`);
* ``"filtered"``: the heights after every operator of ``cutoffs``; simulations are compared
  as drawn (least-squares plane removed). A stationary ACVF fitted there cannot have the
  filtered heights' covariance (:mod:`roughgp.surface_models.fit` says why and what it costs).

Equations:

* ``"eq18"``: a surface, the rotated anisotropic exponential ACVF of eq 18
  (:math:`\sigma_k^2, \lambda_a, \lambda_b, \phi`) plus Gaussian noise :math:`\sigma^2` (eq 8);
* ``"eq18-matern"``: eq 18's rotated anisotropy with a Matérn radial profile of smoothness
  ``nu`` (1.5 or 2.5: smoother surfaces than eq 18's exponential,
  :func:`roughgp.gp.acvf.rotated_matern`), plus Gaussian noise;
* ``"eq21"``: a profile, the spectral mixture of eq 21 (weights, frequencies, spectral
  variances) plus Gaussian noise;
* ``"measured-psd"``: a surface, the measured PSD itself as a 40 x 36 log-polar table (um^4)
  over frequencies ``frequency_min_per_um`` to ``frequency_max_per_um``, the nonparametric
  stationary Gaussian model (:mod:`roughgp.surface_models.measured_psd`); its noise is in the
  PSD (``noise_variance_um2`` 0), its ACVF the inverse DFT of the PSD;
* ``"periodic-mark"``: a periodic machined surface, a deterministic feed mark with Gaussian
  mark-to-mark shifts and depths, plus eq 18 and noise
  (:mod:`roughgp.surface_models.periodic_model`); ``"periodic-mark-profile"`` the same for a
  profile, eq 18's exponential in one dimension on top;
* ``"sm2d"``: a surface, a 2-D spectral mixture (eq 21's family in two dimensions, each
  component a pair of Gaussians at :math:`\pm\boldsymbol\mu_q` with a full covariance given
  by its bandwidths and axes' angle) plus Gaussian noise, for structured or periodic surfaces
  (:mod:`roughgp.surface_models.spectral_mixture`); drawn by exact circulant embedding.

Non-Gaussian heights (``marginal = {"skewness": s, "kurtosis": k}``) are drawn as
:math:`Z = T(X) + e`: the latent surface is the Johnson transform of a pre-distorted GP with the
fitted latent ACVF (:func:`roughgp.non_gaussian.non_gaussian_surface`), and the noise
``e`` is added after it. With the latent share :math:`w = \sigma_k^2 / (\sigma_k^2 + \sigma^2)`,
a sum of independent parts has skewness :math:`w^{3/2}` times and excess kurtosis :math:`w^2`
times the latent one, so the latent targets are the measured ones divided by these factors.
On the measured-psd model the Johnson marginal is drawn by IAAFT toward the Johnson
distribution instead (a transform would change the PSD). The IAAFT marginal (``marginal =
{"method": "iaaft", "quantiles_um": [...], "tail_probability": p, "iterations": n,
"order_scores": [...]}``) keeps the measured heights' quantile function and matches it
exactly, on any surface equation (:mod:`roughgp.surface_models.iaaft`, keyed as
:mod:`roughgp.surface_models.order_scores` says).
"""

from __future__ import annotations

import dataclasses
import json
import math
import weakref
from pathlib import Path

import numpy as np

from roughgp.common.atomic import atomic_output
from roughgp.common.checks import as_generator
from roughgp.common.grid import normalize
from roughgp.common.json_values import plain
from roughgp.gp.noise import GaussianNoise
from roughgp.surface_models.schema import (
    EQUATIONS,
    MAX_FILE_BYTES,
    MODEL_FORMAT,
    STAGES,
    ModelFileError,
    check_fields,
    validate_record,
)

__all__ = ["FittedModel", "MODEL_FORMAT", "MODEL_VERSION", "EQUATIONS", "STAGES", "ModelFileError"]

MODEL_VERSION = 2
#: id -> weak reference of the models whose heights were bounded (FittedModel._bound_heights)
_HEIGHTS_BOUNDED: dict = {}
_MAX_SIMULATE_POINTS = 2 ** 24


@dataclasses.dataclass(frozen=True)
class FittedModel:
    """A fitted surface model (eq 18, its Matérn variant, the measured PSD) or eq 21 profile
    model (module docstring).

    Attributes:
        equation: ``"eq18"``, ``"eq18-matern"``, ``"eq21"``, ``"measured-psd"``, ``"sm2d"``,
            ``"eq18-field"`` (:mod:`roughgp.surface_models.field_model`),
            ``"eq18-population"`` (:mod:`roughgp.surface_models.population_model`) or
            ``"periodic-mark"`` / ``"periodic-mark-profile"``
            (:mod:`roughgp.surface_models.periodic_model`).
        hyperparameters: the names of :data:`EQUATIONS` (units in the names: um, um^2, deg,
            1/um); eq 21's are lists of Q values.
        spacing: the grid spacing of the data, ``(dy, dx)`` (surface) or ``(dx,)`` (profile), um.
        marginal: None (Gaussian heights), ``{"skewness": s, "kurtosis": k}`` of the heights
            (Pearson's kurtosis, 3 for Gaussian; Johnson) or the IAAFT marginal (module
            docstring) that simulations reproduce.
        operators: the operators applied to the data before the fit, e.g.
            ``["F: cylinder ...", "L: Gaussian 250 um"]`` (they are applied to simulations
            too when a model is checked).
        cutoffs: ``{"form": ..., "s_um": ..., "l_um": ...}``: the operators' settings.
        data: what the model was fitted on (file, shape, missing share, points used, ...).
        fit: how (method, log likelihood, seed, seconds, ...).
        stage: ``"form-removed"`` or ``"filtered"``: where in the operator chain the model
            describes the surface (module docstring).
    """

    equation: str
    hyperparameters: dict
    spacing: tuple
    marginal: dict | None = None
    operators: tuple = ()
    cutoffs: dict = dataclasses.field(default_factory=dict)
    data: dict = dataclasses.field(default_factory=dict)
    fit: dict = dataclasses.field(default_factory=dict)
    stage: str = "form-removed"

    def __post_init__(self):
        check_fields(self.equation, self.hyperparameters, self.spacing, self.marginal,
                     self.cutoffs, self.stage, self.operators)

    # ------------------------------------------------------------------ what it is
    @property
    def kind(self) -> str:
        """``"surface"`` or ``"profile"``."""
        return EQUATIONS[self.equation][0]

    @property
    def noise_variance(self) -> float:
        return float(self.hyperparameters["noise_variance_um2"])

    @property
    def recorded_shape(self) -> tuple | None:
        """The one grid the model was fitted on (``data.shape``): ``(NY, NX)``, a profile's
        ``(N,)``; None where no single grid is recorded (several maps, an edited file)."""
        shape = self.data.get("shape") if isinstance(self.data, dict) else None
        rank = 1 if self.kind == "profile" else 2
        if isinstance(shape, (list, tuple)) and len(shape) == rank and all(
                isinstance(n, (int, np.integer)) and not isinstance(n, bool) and n >= 2
                for n in shape):
            return tuple(int(n) for n in shape)
        return None

    def kernel(self):
        """The fitted latent kernel (:mod:`roughgp.gp.kernels`), lengths in um; for the
        measured-psd model a function of lags ``(..., 2)`` in (x, y) order: the ACVF tabulated
        by the inverse DFT of its PSD
        (:class:`~roughgp.surface_models.measured_psd.TabulatedACVF`)."""
        hp = self.hyperparameters
        if self.equation == "eq18-field":
            raise ValueError("the eq18-field model has no single kernel (its parameters vary "
                             "over the map): fill, the calibrated check and the predictive "
                             "draws need a stationary model (fit one with --model eq18)")
        if self.equation == "eq18-population":
            raise ValueError("the eq18-population model has no single kernel (each surface "
                             "draws its own region's parameters): fill, the calibrated check "
                             "and the predictive draws need a stationary model (fit one with "
                             "--model eq18)")
        if self.equation in ("periodic-mark", "periodic-mark-profile"):
            raise ValueError(f"the {self.equation} model has no single kernel (a deterministic "
                             "feed mark plus Gaussian processes): the calibrated check and the "
                             "predictive draws need a stationary model (fit one with --model "
                             "eq18 or sm)")
        if self.equation == "measured-psd":
            from roughgp.surface_models.measured_psd import TabulatedACVF, fitted_shape
            # its lags are read on the grid of the fitted field, at the model's spacing
            return self._keyed(TabulatedACVF(self), (*self.spacing, *fitted_shape(self)))
        if self.equation == "sm2d":
            from roughgp.surface_models.spectral_mixture import Mixture2D, sm2d_acvf
            mixture = Mixture2D.from_hyperparameters(hp)
            return self._keyed(lambda lags: sm2d_acvf(lags, mixture))
        if self.equation == "eq18-matern":
            from roughgp.gp.acvf import rotated_matern
            scales = np.array([hp["lambda_a_um"], hp["lambda_b_um"]], dtype=np.float64)
            variance, angle, nu = float(hp["variance_um2"]), math.radians(hp["angle_deg"]), \
                float(hp["nu"])
            return self._keyed(lambda lags: rotated_matern(lags, variance, scales, angle, nu))
        if self.equation == "eq18":
            from roughgp.gp.kernels import RotatedExponentialKernel
            return RotatedExponentialKernel(hp["variance_um2"],
                                            (hp["lambda_a_um"], hp["lambda_b_um"]),
                                            math.radians(hp["angle_deg"]))
        from roughgp.gp.kernels import SpectralMixtureKernel
        weights = np.asarray(hp["weights_um2"], dtype=np.float64)
        q = weights.size
        return SpectralMixtureKernel(
            q, dim=1, weights=weights,
            means=np.asarray(hp["frequencies_per_um"], dtype=np.float64).reshape(q, 1),
            variances=np.asarray(hp["spectral_variances_per_um2"],
                                 dtype=np.float64).reshape(q, 1))

    def _keyed(self, acvf, context=()):
        """``acvf`` with this model's identity (and ``context``: the numbers beyond the
        hyperparameters that it depends on), so that its circulant embedding is cached between
        draws (:mod:`roughgp.surface_models.keyed_acvf`)."""
        from roughgp.surface_models.keyed_acvf import KeyedACVF, model_key
        return KeyedACVF(acvf, model_key(self.equation, self.hyperparameters, context))

    def latent_variance(self) -> float:
        hp = self.hyperparameters
        if self.equation == "measured-psd":
            from roughgp.surface_models.measured_psd import band_variance
            return band_variance(self)
        if self.equation == "eq18-field":  # the mean over the anchors
            return float(np.mean(hp["variance_um2"]))
        if self.equation == "eq18-population":  # the mean over the regions (log-normal)
            return float(hp["variance_um2"] * math.exp(hp["log_variance_sd"] ** 2 / 2))
        if self.equation in ("periodic-mark", "periodic-mark-profile"):  # mark, depths, rest
            return float(np.var(hp["mark_um"]) + hp["depth_sd_um"] ** 2
                         + hp.get("lay_sd_um", 0.0) ** 2 + hp["variance_um2"])
        if self.kind == "surface" and self.equation != "sm2d":
            return float(hp["variance_um2"])
        return float(np.sum(hp["weights_um2"]))

    def describe(self) -> str:
        """One line: the equation and its hyperparameters."""
        hp = self.hyperparameters
        if self.equation == "measured-psd":
            rows = hp["psd_um4"]
            text = (f"measured PSD ({len(rows)} x {len(rows[0])} log-polar table"
                    f"{', lowest frequencies and axes as measured' if 'core_ratio' in hp else ''}, "
                    f"{hp['frequency_min_per_um']:.4g} to {hp['frequency_max_per_um']:.4g} 1/um), "
                    f"variance {self.latent_variance():.4g} um^2")
        elif self.equation == "sm2d":
            # a peak: a component whose frequency lies further from 0 than its bandwidths
            periods = ", ".join(f"{1 / math.hypot(fx, fy):.4g}" for fx, fy, a, b in
                                zip(hp["frequencies_x_per_um"], hp["frequencies_y_per_um"],
                                    hp["bandwidths_a_per_um"], hp["bandwidths_b_per_um"])
                                if math.hypot(fx, fy) > max(a, b))
            text = (f"2-D spectral mixture: Q = {len(hp['weights_um2'])} components, variance "
                    f"{self.latent_variance():.4g} um^2"
                    + (f", peaks at periods {periods} um" if periods else ", no peak"))
        elif self.equation == "eq18-field":
            rows, cols = len(hp["anchors_y_um"]), len(hp["anchors_x_um"])
            ranges = ", ".join(f"{key.rsplit('_', 1)[0]} {np.min(hp[key]):.4g} to "
                               f"{np.max(hp[key]):.4g} {unit}" for key, unit in (
                                   ("variance_um2", "um^2"), ("lambda_a_um", "um"),
                                   ("lambda_b_um", "um"), ("angle_deg", "deg")))
            text = f"eq 18 with parameter fields on {rows} x {cols} anchors: {ranges}"
            text += "".join(f"; {n.rsplit('_', 1)[0]} steps at {s['axis']} = {s['at_um']:.4g}"
                            f" um" for n, s in hp.get("steps", {}).items())
        elif self.equation == "eq18-population":
            text = (f"eq 18 over a population of {hp['regions']} regions: variance "
                    f"{hp['variance_um2']:.4g} um^2 (x/ {math.exp(hp['log_variance_sd']):.3g} "
                    f"between regions), lambda_a {hp['lambda_a_um']:.4g} um (x/ "
                    f"{math.exp(hp['log_lambda_a_sd']):.3g}), lambda_b {hp['lambda_b_um']:.4g} "
                    f"um (x/ {math.exp(hp['log_lambda_b_sd']):.3g}), angle "
                    f"{hp['angle_deg']:.1f} +- {hp['angle_sd_deg']:.1f} deg")
        elif self.equation == "periodic-mark":
            from roughgp.surface_models.periodic_draw import mark_of
            text = (f"periodic mark: feed {hp['feed_um']:.5g} um along "
                    f"{'x' if hp['feed_direction_deg'] == 0 else 'y'}, mark height "
                    f"{mark_of(self).height:.4g} um; per mark a shift of sd {hp['shift_sd_um']:.3g} um "
                    f"(rho {hp['shift_rho']:.2f}) and a depth of sd {hp['depth_sd_um']:.3g} um "
                    f"(rho {hp['depth_rho']:.2f}), varying along the lay by sd "
                    f"{hp['lay_sd_um']:.3g} um over {hp['depth_length_um']:.4g} um; roughness eq 18: variance {hp['variance_um2']:.4g} um^2, lambda_a "
                    f"{hp['lambda_a_um']:.4g} um, lambda_b {hp['lambda_b_um']:.4g} um, angle "
                    f"{hp['angle_deg']:.1f} deg")
        elif self.equation == "periodic-mark-profile":
            from roughgp.surface_models.periodic_draw import mark_of
            text = (f"periodic mark (profile): feed {hp['feed_um']:.5g} um, mark height "
                    f"{mark_of(self).height:.4g} um; per mark a shift of sd "
                    f"{hp['shift_sd_um']:.3g} um (rho {hp['shift_rho']:.2f}) and a depth of sd "
                    f"{hp['depth_sd_um']:.3g} um (rho {hp['depth_rho']:.2f}); roughness eq 18 "
                    f"in 1-D: variance {hp['variance_um2']:.4g} um^2, lambda "
                    f"{hp['lambda_um']:.4g} um")
        elif self.kind == "surface":
            name = "eq 18" if self.equation == "eq18" else f"eq 18 with Matern nu = {hp['nu']:g}"
            text = (f"{name}: variance {hp['variance_um2']:.4g} um^2, lambda_a "
                    f"{hp['lambda_a_um']:.4g} um, lambda_b {hp['lambda_b_um']:.4g} um, angle "
                    f"{hp['angle_deg']:.1f} deg")
        else:
            q = len(np.atleast_1d(hp["weights_um2"]))
            text = f"eq 21: Q = {q} spectral-mixture components, variance " \
                   f"{self.latent_variance():.4g} um^2"
        text += f"; noise variance {self.noise_variance:.3g} um^2"
        if self.marginal_method == "iaaft":
            q = self.marginal["quantiles_um"]
            text += (f"; IAAFT heights ({len(q)} measured quantiles, {q[0]:.4g} to {q[-1]:.4g} "
                     f"um, at most {self.marginal['iterations']} rounds)")
        elif self.marginal is not None:
            text += (f"; Johnson heights (skewness {self.marginal['skewness']:.3g}, kurtosis "
                     f"{self.marginal['kurtosis']:.3g})")
        return text

    # ------------------------------------------------------------------ drawing
    def simulate(self, shape, *, seed=None, spacing=None, n_samples=None, method="auto"):
        """Draws from the model on a grid of ``shape`` (``(ny, nx)``, or ``n`` / ``(n,)`` for
        a profile model) at the model's spacing (or ``spacing``, um).

        Returns ``z`` of ``shape`` (``(n_samples, *shape)`` when ``n_samples`` is an int):
        the latent GP (Johnson-transformed when the model has a ``marginal``) plus the noise.
        """
        from roughgp.sampling import sample_grid
        from roughgp.surface_models.psd_table import population_slices
        shape = (int(shape),) if np.ndim(shape) == 0 else tuple(int(n) for n in shape)
        want = 2 if self.kind == "surface" else 1
        if len(shape) != want or min(shape) < 1:
            raise ValueError(f"shape must be {'(ny, nx)' if want == 2 else '(n,)'} of positive "
                             f"integers for a {self.kind} model, got {shape}")
        count = 1 if n_samples is None else int(n_samples)
        if count < 1:
            raise ValueError(f"n_samples must be >= 1, got {n_samples!r}")
        if count * math.prod(shape) > _MAX_SIMULATE_POINTS:
            raise ValueError(f"n_samples x shape = {count * math.prod(shape)} points exceeds "
                             f"{_MAX_SIMULATE_POINTS} (2**24): draw fewer or smaller surfaces")
        shape, spacing = normalize(shape, self.spacing if spacing is None else spacing)
        self._bound_heights()  # before drawing: no height beyond the readers' 1 m
        rng = as_generator(seed)
        if self.equation == "eq18-field":
            from roughgp.surface_models.field_draw import draw_field_model
            return self._returned(draw_field_model(self, shape, spacing, rng, count), n_samples)
        if self.equation == "eq18-population":
            from roughgp.surface_models.population_draw import draw_population_model
            return self._returned(draw_population_model(self, shape, spacing, rng, count),
                                  n_samples)
        if self.equation == "periodic-mark-profile":
            from roughgp.surface_models.periodic_draw import draw_periodic_profile
            return self._returned(draw_periodic_profile(self, shape[0], spacing[0], rng, count),
                                  n_samples)
        if self.equation == "periodic-mark":
            from roughgp.surface_models.periodic_draw import draw_periodic_model
            return self._returned(draw_periodic_model(self, shape, spacing, rng, count),
                                  n_samples)
        if self.equation == "sm2d":
            from roughgp.surface_models.spectral_mixture import Mixture2D, check_embeddable
            check_embeddable(Mixture2D.from_hyperparameters(self.hyperparameters), shape,
                             spacing)
            method = "circulant" if method == "auto" else method  # exact (spectral_mixture)
        remap = self.marginal is not None and (self.equation == "measured-psd"
                                               or self.marginal_method == "iaaft")
        if self.equation == "measured-psd":
            from roughgp.surface_models.measured_psd import draw_psd_model
            return self._returned(draw_psd_model(self, shape, spacing, rng, count,
                                                 self._remapper(spacing) if remap
                                                 else None), n_samples)
        if remap:  # on twice the field's points, then cropped (roughgp.surface_models.iaaft)
            big = tuple(s.stop for s in population_slices(shape))
            latent = sample_grid(self.kernel(), big, spacing=spacing, n_samples=count,
                                 method=method, seed=rng)
            z = GaussianNoise(self.noise_variance).sample(latent, seed=rng)
            crop = (slice(None),) + tuple(slice(0, n) for n in shape)
            remapped = self._remapper(spacing)
            return self._returned(np.stack([remapped(f) for f in z])[crop], n_samples)
        if self.marginal is None:
            latent = sample_grid(self.kernel(), shape, spacing=spacing, n_samples=count,
                                 method=method, seed=rng)
        else:
            from roughgp.non_gaussian import non_gaussian_surface
            w = self.latent_variance() / (self.latent_variance() + self.noise_variance)
            skew = float(self.marginal["skewness"]) / w ** 1.5
            kurt = 3.0 + (float(self.marginal["kurtosis"]) - 3.0) / w ** 2
            try:
                latent, _ = non_gaussian_surface(
                    self.kernel(), shape, skewness=skew, kurtosis=kurt, spacing=spacing,
                    seed=rng, n_samples=count,
                    method="circulant" if method == "auto" else method)
            except ValueError as exc:
                if "kurtosis" not in str(exc):
                    raise
                raise ValueError(self._latent_marginal_refusal(w, skew, kurt, exc)) from None
        z = GaussianNoise(self.noise_variance).sample(latent, seed=rng)
        return self._returned(z, n_samples)

    def _bound_heights(self, source="the model") -> None:
        """:func:`~roughgp.surface_models.height_bound.check_height_bound`, once per model (a
        check draws 99 times from one; the measured PSD's variance costs an FFT)."""
        checked = _HEIGHTS_BOUNDED.get(id(self))
        if checked is not None and checked() is self:
            return
        from roughgp.surface_models.height_bound import check_height_bound
        check_height_bound(self, source)
        if len(_HEIGHTS_BOUNDED) > 4096:  # forget the models gone
            for key in [k for k, ref in _HEIGHTS_BOUNDED.items() if ref() is None]:
                del _HEIGHTS_BOUNDED[key]
        _HEIGHTS_BOUNDED[id(self)] = weakref.ref(self)  # outside the object: its __dict__ is
        # its fields (FittedModel(**model.__dict__) copies a model)

    def _latent_marginal_refusal(self, w, skew, kurt, exc) -> str:
        """Why the Johnson marginal cannot be drawn, in the file's fields: the latent surface
        carries a share ``w`` of the variance, so the heights' skewness and kurtosis ask it
        for ``skew`` and ``kurt`` (``exc``: the Johnson fit's refusal of those)."""
        s, k = float(self.marginal["skewness"]), float(self.marginal["kurtosis"])
        least = 3.0 + s * s / w - 2.0 * w * w  # kurt > skew**2 + 1, in the file's terms
        return (f"the marginal's skewness {s:.4g} and kurtosis {k:.4g} cannot be drawn with "
                f"this noise: the latent surface carries {w:.3g} of the variance "
                f"(variance against noise_variance_um2 {self.noise_variance:.4g} um^2), so it "
                f"would need skewness {skew:.4g} and kurtosis {kurt:.4g} ({exc}); give a "
                f"marginal kurtosis above {least:.4g}, a smaller skewness or a smaller "
                f"noise_variance_um2")

    @staticmethod
    def _returned(z, n_samples):
        return z if n_samples is not None else z[0]

    @property
    def marginal_method(self) -> str:
        """``"gaussian"`` (no marginal), ``"johnson"`` or ``"iaaft"``."""
        if self.marginal is None:
            return "gaussian"
        return self.marginal.get("method", "johnson")

    def _remapper(self, spacing):
        """The function that gives a Gaussian draw (at ``spacing``) the
        model's height distribution by IAAFT (:mod:`roughgp.surface_models.iaaft`): the
        stored quantiles, in the band above the L-filter's cut-off when the marginal has
        ``above_l_um`` (:func:`~roughgp.surface_models.iaaft.iaaft_above`), or, for the
        measured-psd model with a Johnson marginal, the Johnson distribution of the model's
        skewness, kurtosis, variance and mean (its transform of a Gaussian field would change
        the PSD)."""
        from roughgp.surface_models import iaaft
        cut = self.marginal.get("above_l_um") if self.marginal_method == "iaaft" else None
        sds = {}   # the remapped field's sd over realisations, by shape (remap_scale)

        def remapped(field):
            if field.shape not in sds:
                from roughgp.surface_models.measured_psd import remap_scale
                sds[field.shape] = remap_scale(self, field.shape, spacing, cut)
            return self._remapped(field, sds[field.shape])
        if cut is None:
            return remapped
        return lambda field: iaaft.iaaft_above(field, remapped, cut, spacing)

    def _remapped(self, field, sd):
        """``field`` given the model's height distribution by IAAFT (:meth:`_remapper`), its
        sample the field's own normal scores ``field / sd`` through the target's quantile
        function (:mod:`roughgp.surface_models.iaaft`: the spread of a correlated surface)."""
        from roughgp.surface_models import iaaft
        scores = field / sd
        if self.marginal_method == "iaaft":
            values = iaaft.marginal_values(self.marginal, scores)
            iterations = int(self.marginal["iterations"])
        else:
            from roughgp.non_gaussian.johnson import johnson_for
            johnson = johnson_for(self.marginal["skewness"], self.marginal["kurtosis"],
                                  self.latent_variance())
            values = np.asarray(johnson.transform(scores), dtype=np.float64) \
                + float(self.hyperparameters.get("mean_um", 0.0))
            iterations = iaaft.ITERATIONS
        return iaaft.iaaft(field, np.sort(values, axis=None), iterations)[0]

    # ------------------------------------------------------------------ the file
    def to_dict(self) -> dict:
        from roughgp.common.version import VERSION
        return plain({"format": MODEL_FORMAT, "version": MODEL_VERSION,
                      "equation": self.equation, "kind": self.kind, "stage": self.stage,
                      "description": self.describe(), "hyperparameters": self.hyperparameters,
                      "spacing_um": [float(d) for d in self.spacing], "marginal": self.marginal,
                      "operators": list(self.operators), "cutoffs": self.cutoffs,
                      "data": self.data, "fit": self.fit, "roughgp_version": VERSION},
                     nan_as_null=False)  # a model file writes NaN (allow_nan in save)

    @classmethod
    def from_dict(cls, values, source="the model") -> "FittedModel":
        """A model from the parsed JSON of a model file, validated
        (:func:`~roughgp.surface_models.schema.validate_record`) and its heights bounded
        (:func:`~roughgp.surface_models.height_bound.check_height_bound`)."""
        model = cls(**validate_record(values, source))
        model._bound_heights(source)
        return model

    def save(self, path) -> Path:
        """Write the model file whole or not at all (:func:`roughgp.common.atomic.atomic_output`:
        a temporary file renamed over ``path``; an interrupted save leaves ``path`` as it was).
        Missing folders are made. Returns ``path``."""
        path = Path(path)
        text = json.dumps(self.to_dict(), indent=2, allow_nan=True) + "\n"
        with atomic_output(path) as partial:
            partial.write_text(text)
        return path

    @classmethod
    def load(cls, path) -> "FittedModel":
        path = Path(path)
        if path.is_file() and path.stat().st_size > MAX_FILE_BYTES:
            raise ModelFileError(f"{path} is larger than a model file can be "
                                 f"({MAX_FILE_BYTES} bytes)")
        try:
            values = json.loads(path.read_text())
        except UnicodeDecodeError:
            raise ModelFileError(f"{path} is not a text (JSON) model file") from None
        except json.JSONDecodeError as exc:
            raise ModelFileError(f"{path} is not valid JSON ({exc.msg}, line {exc.lineno})") \
                from None
        except RecursionError:
            raise ModelFileError(f"{path} is nested too deeply to be a model file") from None
        return cls.from_dict(values, source=str(path))

