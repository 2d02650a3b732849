r"""A ladder of surface models, fitted to one measurement and chosen by a held-out predictive
score (beyond the paper).

The rungs (:data:`RUNGS`), each a model file that ``simulate --from``, ``check`` and ``fill
--model`` read:

* ``"eq18"``: the paper's rotated anisotropic exponential ACVF plus noise (eq 18, eq 8);
* ``"matern"``: eq 18's anisotropy with a smoother Matérn profile (:math:`\nu` = 1.5 by
  default, or 2.5);
* ``"sm"``: a 2-D spectral mixture (eq 21/22's family in two dimensions,
  :mod:`roughgp.surface_models.spectral_mixture`): a broad component and peaks for a lay, a
  period or its harmonics, for structured or periodic surfaces;
* ``"psd"``: the measured PSD itself (:mod:`roughgp.surface_models.measured_psd`), the bound of
  what any stationary Gaussian model can do on the file.

Each comes with the height distribution asked for (``marginal``: Gaussian, Johnson or IAAFT).
:func:`choose_model` holds out measured points in small discs
(:func:`roughgp.filling.self_check.held_out_points`, as the fill's self-check does),
fits every rung without them, predicts them by kriging with the rung's covariance (eq 18's or
the Matérn ACVF plus noise; the spectral mixture's in closed form; the PSD model's ACVF
tabulated by the inverse DFT of its PSD) and scores the prediction by its mean squared error
at the held-out heights. It chooses the lowest rung whose error is within one standard error
of the best (:func:`roughgp.filling.self_check.mse_difference`, robust to the errors'
correlation within a disc): a richer model must predict clearly better to be chosen. The
chosen rung is then fitted again on all the measured points. The score rates the covariance at
short lags (a hole's neighbourhood); whether the model reproduces the measurement's texture
parameters is :func:`roughgp.checking.model_check.check_model`'s question, asked of the model
chosen.
"""

from __future__ import annotations

import dataclasses
import time

import numpy as np

from roughgp.common.checks import surface_array
from roughgp.common.grid import normalize
from roughgp.filling.self_check import (
    CHECK_SHARE,
    MIN_CHECK_POINTS,
    FillSelfCheck,
    held_out_points,
    mse_difference,
    self_check_fill,
)
from roughgp.surface_models.chain import form_removed
from roughgp.surface_models.fit import fit_psd_model, fit_sm_model, fit_surface_model
from roughgp.surface_models.model import FittedModel

__all__ = ["RUNGS", "Rung", "LadderChoice", "fit_rung", "choose_model"]

RUNGS = ("eq18", "matern", "sm", "psd")  #: the rungs, simplest first


@dataclasses.dataclass(frozen=True)
class Rung:
    """One rung's fit without the held-out points and its score.

    Attributes:
        name: ``"eq18"``, ``"matern"``, ``"sm"`` or ``"psd"``.
        model: the model fitted without the held-out points.
        check: the kriging of the held-out points with it (RMSE, band coverage, ...).
        seconds: the fit and the kriging.
        refused: why the rung could not be fitted (then ``model`` and ``check`` are None),
            else None.
    """

    name: str
    model: FittedModel | None
    check: FillSelfCheck | None
    seconds: float
    refused: str | None = None

    @property
    def rmse(self) -> float:
        return float("nan") if self.check is None else self.check.rmse["GP"]


@dataclasses.dataclass(frozen=True)
class LadderChoice:
    """What :func:`choose_model` returns: every rung scored, the chosen one, why, and its model
    fitted on all the measured points."""

    rungs: tuple
    chosen: str
    reason: str
    model: FittedModel
    range_notes: tuple = ()


def fit_rung(name, z, spacing, *, form="plane", s=None, l=None, degree=2, axis="auto",
             marginal="gaussian", seed=0, block=24, n_blocks=12, nu=1.5, data=None,
             likelihood="blocks"):
    """``(model, range_notes)``: rung ``name`` (:data:`RUNGS`) fitted to ``z`` (NaN where
    unmeasured); ``nu``: the Matérn rung's smoothness (1.5 or 2.5); ``likelihood``: eq 18's
    and the Matérn rung's (:data:`~roughgp.surface_models.fit.LIKELIHOODS`)."""
    chain = dict(form=form, s=s, l=l, degree=degree, axis=axis, seed=seed, data=data)
    if name == "psd":
        return fit_psd_model(z, spacing, marginal=marginal, **chain).model, ()
    if name == "sm":
        result = fit_sm_model(z, spacing, marginal=marginal, **chain)
        return result.model, result.range_notes
    if name not in ("eq18", "matern"):
        raise ValueError(f"the rung must be one of {list(RUNGS)}, got {name!r}")
    if name == "matern" and nu not in (1.5, 2.5):
        raise ValueError(f"nu of the matern rung must be 1.5 or 2.5, got {nu!r}")
    result = fit_surface_model(z, spacing, block=block, n_blocks=n_blocks, marginal=marginal,
                               nu=0.5 if name == "eq18" else nu, likelihood=likelihood, **chain)
    return result.model, result.range_notes


def _better(rungs):
    """The simplest rung within one standard error of the best, and the sentence why."""
    best = min(rungs, key=lambda r: r.rmse)
    for i, rung in enumerate(rungs):
        if rung is best:  # every simpler rung was more than a standard error worse
            simpler = [r.name for r in rungs[:i]]
            richer = [r.name for r in rungs[i + 1:]]
            return rung, (f"{best.name} predicts the held-out points best (RMSE "
                          f"{best.rmse:.4g} um)"
                          + (f"; the simpler {', '.join(simpler)} clearly worse"
                             if simpler else "")
                          + (f"; the richer {', '.join(richer)} no better" if richer else ""))
        excess, se = mse_difference(rung.check, best.check)
        if excess <= se:
            return rung, (f"{rung.name} is the simplest within one standard error of the best "
                          f"({best.name}, RMSE {best.rmse:.4g} um; {rung.name} {rung.rmse:.4g} "
                          f"um, its excess mean squared error {excess:.3g} um^2 <= the standard "
                          f"error {se:.3g} um^2)")
    return best, ""  # not reached: the loop meets the best


def choose_model(z, spacing=1.0, *, rungs=RUNGS, form="plane", s=None, l=None, degree=2,
                 axis="auto", marginal="gaussian", seed=0, block=24, n_blocks=12, nu=1.5,
                 data=None, progress=None, likelihood="blocks") -> LadderChoice:
    """Fit each of ``rungs`` to ``z`` without held-out measured points, score the kriging of
    those, choose, and fit the chosen rung on all points (module docstring). A rung whose fit
    is refused (a model that cannot be simulated on the grid, ...) is kept with the reason and
    left out of the choice. ``progress``: called with each :class:`Rung` as it is scored.
    Raises ``ValueError`` when too few points are measured to hold some out, or when no rung
    can be fitted. ``likelihood``: eq 18's and the Matérn rung's
    (:func:`fit_rung`)."""
    arr = surface_array(z)
    unknown = [r for r in rungs if r not in RUNGS]
    if unknown or not rungs:
        raise ValueError(f"rungs must be a non-empty selection of {list(RUNGS)}, got "
                         f"{list(rungs)!r}")
    _, spacing = normalize(arr.shape, spacing)
    settings = dict(form=form, s=s, l=l, degree=degree, axis=axis, marginal=marginal,
                    seed=seed, block=block, n_blocks=n_blocks, nu=nu, data=data,
                    likelihood=likelihood)
    residual = form_removed(arr, spacing, {"form": form, "degree": degree, "axis": axis}).sl
    held_out = held_out_points(np.isfinite(residual), seed)
    if held_out is None:
        raise ValueError(f"{int(np.isfinite(residual).sum())} measured points are too few to "
                         f"hold some out and choose a model (at least "
                         f"{MIN_CHECK_POINTS / CHECK_SHARE:.0f} are needed)")
    hidden = np.where(held_out, np.nan, arr)
    scored = []
    for name in rungs:
        start = time.perf_counter()
        try:
            model, _ = fit_rung(name, hidden, spacing, **settings)
        except ValueError as error:   # a rung the map cannot give (say why, go on)
            rung = Rung(name, None, None, time.perf_counter() - start,
                        str(error).splitlines()[0])
        else:
            check = self_check_fill(residual, model.kernel(),
                                    noise_variance=model.noise_variance, spacing=spacing,
                                    held_out=held_out,
                                    nu=float(model.hyperparameters.get("nu", 0.5)))
            rung = Rung(name, model, check, time.perf_counter() - start)
        scored.append(rung)
        if progress is not None:
            progress(rung)
    fitted = [r for r in scored if r.refused is None]
    if not fitted:
        raise ValueError("no rung of the ladder could be fitted: " + "; ".join(
            f"{r.name}: {r.refused}" for r in scored))
    chosen, reason = _better(fitted)
    refused = {r.name: r.refused for r in scored if r.refused is not None}
    if refused:
        reason += "; refused: " + ", ".join(refused)
    model, notes = fit_rung(chosen.name, arr, spacing, **settings)
    scores = {r.name: r.rmse for r in fitted}
    model = dataclasses.replace(model, fit={**model.fit, "chosen_by": reason,
                                            "held_out_rmse_um": scores,
                                            **({"refused_rungs": refused} if refused else {})})
    return LadderChoice(tuple(scored), chosen.name, reason, model, tuple(notes))
