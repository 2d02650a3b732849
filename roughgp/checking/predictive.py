r"""Simulations that carry the fit's uncertainty: a parametric bootstrap of the fit (beyond the
paper; issue 40).

A model fitted to one crop of a surface is a point estimate :math:`\hat\theta` of the
variance, the lengths and the lay of eq 18 (or of another rung of the ladder). A 256 x 256
crop holds only a few wavelengths near the L-filter's cut-off, so :math:`\hat\theta` is
uncertain, and simulations drawn from :math:`\hat\theta` alone (the *plug-in* simulations)
are too alike: another crop of the same surface, whose parameters are :math:`\theta` and
not :math:`\hat\theta`, falls outside their range more often than the check's nominal
:math:`2 / (n + 1)`.

The *predictive* simulations draw the parameters first: :math:`B` bootstrap measurements
:math:`y^*_b` are drawn from :math:`\hat\theta` on the grid the model was fitted on, each is
refitted the way the model was fitted (:func:`roughgp.checking.calibrated.refit_like`: the
same rung, marginal, operators and blocks), and simulation :math:`i` is drawn from refit
:math:`\hat\theta^*_{i \bmod B}`. The spread of :math:`\hat\theta^*` around :math:`\hat\theta`
stands for the spread of :math:`\hat\theta` around :math:`\theta` (Efron and Tibshirani 1993,
ch. 6; Harris 1989's bootstrap predictive distribution), so the simulations spread as new
measurements of the surface would. The bootstrap copies are complete grids of the fitted
data's shape (``model.data["shape"]``): holes of the fitted crop are not recorded in the model
file, so a crop with many holes gets copies a little more informative than it was.

Surface models of stage ``"form-removed"`` of the rungs
:data:`~roughgp.checking.calibrated.RUNG_OF_EQUATION` only (what :func:`refit_like` refits);
:func:`predictive_refusal` says why another cannot be. What it buys out of sample is measured
in ``benchmarks/held_out_calibration.py`` (the chapter "Does the model check say no when it
should?").
"""

from __future__ import annotations

import dataclasses

import numpy as np

from roughgp.checking.calibrated import refit_like, refusal
from roughgp.surface_models.model import FittedModel

__all__ = ["MAX_MODELS", "CENTRES", "SOURCES", "bootstrap_models", "recentred",
           "predictive_refusal", "fitted_shape", "predictive_models", "predictive_draws"]

MAX_MODELS = 99  #: the most bootstrap refits (each a fit)
#: where the predictive models come from: bootstrap refits (:func:`bootstrap_models`),
#: parameter sets of the Whittle sandwich covariance (:mod:`roughgp.checking.sandwich_draws`),
#: or a bootstrap of the fitted map's tiles (:mod:`roughgp.checking.tile_bootstrap`)
SOURCES = ("refits", "sandwich", "tiles")
#: where the predictive draws are centred: as refitted, on the fit, or on the bias-corrected fit
CENTRES = ("refits", "fit", "bias-corrected")
#: the positive scale parameters recentred (in logs) by :func:`recentred`, per equation
_SCALES = {"eq18": ("variance_um2", "lambda_a_um", "lambda_b_um", "noise_variance_um2"),
           "eq18-matern": ("variance_um2", "lambda_a_um", "lambda_b_um", "noise_variance_um2")}


def fitted_shape(model: FittedModel, default) -> tuple:
    """The grid the model was fitted on (:attr:`FittedModel.recorded_shape`), else
    ``default``."""
    shape = model.recorded_shape
    if shape is None or len(shape) != 2:
        return None if default is None else tuple(int(n) for n in default)
    return shape


def predictive_refusal(model: FittedModel) -> str | None:
    """Why ``model``'s fit cannot be bootstrapped, or None."""
    why = refusal(model)
    return None if why is None else why.replace("the calibrated check refits",
                                                "the predictive simulations refit").replace(
        "the calibrated check", "the predictive simulations")


def recentred(model: FittedModel, refits, centre="bias-corrected") -> tuple:
    r"""The refits moved so that their scale parameters (variance, lengths, noise; in logs)
    centre where ``centre`` says, their spread kept (eq 18 and its Matérn variant; other rungs
    are returned as refitted):

    - ``"refits"``: as refitted (centred where the fit lands on copies of the fitted model:
      for a fit biased low, lower than the fit);
    - ``"fit"``: on the fit, :math:`\log\theta^*_b - \overline{\log\theta^*} +
      \log\hat\theta`;
    - ``"bias-corrected"``: on the bootstrap's bias-corrected fit, :math:`\log\theta^*_b -
      \overline{\log\theta^*} + (2 \log\hat\theta - \overline{\log\theta^*})`
      (Efron and Tibshirani 1993, section 10.6: the fit's bias estimated by the refits').
    """
    if centre not in CENTRES:
        raise ValueError(f"centre must be one of {', '.join(CENTRES)}, got {centre!r}")
    refits = tuple(refits)
    names = _SCALES.get(model.equation, ())
    if centre == "refits" or not names or len(refits) < 2:
        return refits
    shift = {}
    for name in names:
        fitted = np.log(float(model.hyperparameters[name]))
        mean = float(np.mean([np.log(float(r.hyperparameters[name])) for r in refits]))
        shift[name] = fitted - mean if centre == "fit" else 2.0 * (fitted - mean)
    out = []
    for r in refits:
        hp = dict(r.hyperparameters)
        for name, delta in shift.items():
            hp[name] = float(np.exp(np.log(float(hp[name])) + delta))
        out.append(dataclasses.replace(r, hyperparameters=hp))
    return tuple(out)


def bootstrap_models(model: FittedModel, n_models, *, shape=None, spacing=None, seed=0,
                     centre="bias-corrected", progress=None) -> tuple:
    """``n_models`` refits of bootstrap measurements drawn from ``model`` (module docstring).

    Args:
        model: a surface :class:`~roughgp.surface_models.model.FittedModel` of stage
            ``"form-removed"`` (:func:`predictive_refusal`).
        n_models: B, an integer in [1, :data:`MAX_MODELS`].
        shape: of the bootstrap measurements (default: the fitted data's,
            :func:`fitted_shape`).
        spacing: their spacing (default: the model's).
        seed: an integer >= 0; the same seed gives the same refits.
        centre: where the draws are centred (:func:`recentred`).
        progress: None or a function called with ``(b, B)`` after each refit.

    Returns:
        a tuple of B FittedModels.
    """
    if not isinstance(n_models, (int, np.integer)) or not 1 <= n_models <= MAX_MODELS:
        raise ValueError(f"n_models must be an integer in [1, {MAX_MODELS}], got {n_models!r}")
    if not isinstance(seed, (int, np.integer)) or seed < 0:
        raise ValueError(f"seed must be an integer >= 0, got {seed!r}")
    if centre not in CENTRES:
        raise ValueError(f"centre must be one of {', '.join(CENTRES)}, got {centre!r}")
    why = predictive_refusal(model)
    if why:
        raise ValueError(why)
    if shape is None:
        shape = fitted_shape(model, None)
        if shape is None:
            raise ValueError("shape: the model file records no fitted shape (data.shape); "
                             "give the bootstrap measurements' shape")
    shape = tuple(int(n) for n in shape)
    spacing = model.spacing if spacing is None else spacing
    copies = np.random.default_rng([int(seed), 4])
    refits = []
    for b in range(int(n_models)):
        copy = model.simulate(shape, seed=copies, spacing=spacing)
        try:
            refits.append(refit_like(model, copy, spacing))
        except ValueError as error:
            raise ValueError(f"bootstrap copy {b + 1} of {n_models} cannot be refitted: "
                             f"{error}") from None
        if progress is not None:
            progress(b + 1, int(n_models))
    return recentred(model, refits, centre)


def predictive_models(model: FittedModel, n_models, *, source="refits", seed=0,
                      progress=None, fitted=None, spread=None) -> tuple[tuple, tuple]:
    """``(models, held)``: the ``n_models`` models the predictive simulations draw from in turn
    (``check_model(..., models=...)``), from ``source`` (:data:`SOURCES`):

    - ``"refits"``: :func:`bootstrap_models` (bias-corrected; any rung the calibrated check
      refits); ``held`` is empty;
    - ``"sandwich"``: eq 18 parameter sets from the Whittle sandwich covariance of the model on
      its fitted grid (:func:`~roughgp.checking.sandwich_draws.sandwich_models` with the
      expected information: the model file keeps no heights), no refits; ``held``: the
      hyperparameters the grid does not determine, kept at the fit;
    - ``"tiles"``: :func:`~roughgp.checking.tile_bootstrap.tile_bootstrap_models` of the map
      the model was fitted on, ``fitted = (z, spacing)``, its variance ratios raised to
      ``spread`` (default: the model's own
      :func:`~roughgp.checking.tile_bootstrap.tile_spread_factor`); ``held`` is empty.

    ``progress``: as :func:`bootstrap_models` (refits only). Raises ValueError saying why the
    model cannot be drawn so.
    """
    if source not in SOURCES:
        raise ValueError(f"source must be one of {', '.join(SOURCES)}, got {source!r}")
    if source == "tiles":
        if fitted is None:
            raise ValueError("the tile bootstrap needs the map the model was fitted on "
                             "(fitted = (z, spacing))")
        from roughgp.checking.tile_bootstrap import tile_bootstrap_models
        z, spacing = fitted
        return tile_bootstrap_models(model, z, n_models, spacing=spacing, seed=seed,
                                     spread=spread), ()
    shape = fitted_shape(model, None)
    if shape is None:
        raise ValueError("the model file records no fitted shape (data.shape): its "
                         + ("sandwich" if source == "sandwich" else "bootstrap measurements")
                         + " have no grid")
    if source == "refits":
        return bootstrap_models(model, n_models, shape=shape, seed=seed,
                                progress=progress), ()
    from roughgp.checking.sandwich_draws import sandwich_models
    drawn = sandwich_models(model, None, np.ones(shape, dtype=bool), n_models, seed=seed)
    return drawn.models, drawn.held


def predictive_draws(model: FittedModel, shape, *, source="refits", seed=None, spacing=None,
                     n_samples=None, fitted=None, progress=None) -> tuple:
    """``(z, models, held)``: new surfaces drawn from the predictive distribution of ``model``
    (module docstring), as ``roughgp simulate --from MODEL --predictive-from SOURCE`` does:
    each draw's model first, from ``source`` (:func:`predictive_models`; ``fitted = (z,
    spacing)`` of the fitted map for ``"tiles"``), then the surface from it. So a set of draws
    spreads as the surfaces of the part would, the fit's uncertainty carried, where plug-in
    draws (``model.simulate``) spread as one crop's.

    Args:
        shape, spacing: as :meth:`~roughgp.surface_models.model.FittedModel.simulate`.
        seed: an integer >= 0 (the same seed gives the same models and draws), None (fresh)
            or a numpy Generator; the models are drawn from a stream of their own.
        n_samples: None (one draw, ``z`` of ``shape``) or the number of draws (``z`` of
            ``(n_samples, *shape)``, each from its own model), at most :data:`MAX_MODELS`.

    ``models``: the models drawn from (one per draw); ``held``: as :func:`predictive_models`.
    """
    from roughgp.common.checks import as_generator, check_integer
    count = 1 if n_samples is None else n_samples
    check_integer("n_samples", count, 1, MAX_MODELS)
    rng = as_generator(seed)
    parameter_seed = int(rng.integers(0, 2 ** 32))
    models, held = predictive_models(model, count, source=source, seed=parameter_seed,
                                     progress=progress, fitted=fitted)
    draws = [m.simulate(shape, seed=rng, spacing=spacing) for m in models]
    z = draws[0] if n_samples is None else np.stack(draws)
    return z, tuple(models), tuple(held)
