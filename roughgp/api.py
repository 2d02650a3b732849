"""The verbs: read, fit, simulate, check, fill, and texture, each a thin face over the library.

::

    import roughgp

    measured = roughgp.read("data/sample-land.x3p")         # any format; heights in µm
    model = roughgp.fit(measured, form="cylinder", l=250.0)   # eq 18 after the F-operator
    new = roughgp.simulate(model, (256, 918), seed=1)         # a new land like it
    print(roughgp.check(model, measured).outside)             # what the model fails to reproduce
    filled = roughgp.fill(measured).filled                    # the unmeasured points filled
    print(roughgp.texture(measured).parameters)               # ISO 25178-2 after F, S, L

A ``surface`` is a :class:`~roughgp.io.measurement.Measurement` (what :func:`read` returns:
heights in µm, ``z[iy, ix]`` or a profile ``z[ix]``, NaN where unmeasured, with its spacing) or
an array of heights with ``spacing`` (a scalar or ``(dy, dx)``, µm; default: the measurement's,
or 1). A ``model`` is a :class:`~roughgp.surface_models.model.FittedModel` or the path of its
model file. Each verb calls one function of the library and returns what it returns; the
modules named in each docstring hold the options and the details. ``roughgp`` commands call
the same faces (``roughgp texture``, ``check``, ``fill``, ``simulate --from`` and the input of
every command). Nothing is imported until a verb is called: ``import roughgp`` imports neither
numpy nor torch.

May import: every package of roughgp below :mod:`roughgp.experiments`.
"""

from __future__ import annotations

import os

__all__ = ["read", "fit", "simulate", "check", "fill", "texture", "PRESETS"]

#: the surfaces :func:`simulate` draws by name: the paper's figures 2 and 3
PRESETS = ("ground", "honed")


def _heights(surface, spacing):
    """``(z, spacing)`` of a Measurement (its spacing unless one is given) or of an array."""
    if hasattr(surface, "z") and hasattr(surface, "spacing"):
        return surface.z, surface.spacing if spacing is None else spacing
    import numpy as np
    return np.asarray(surface, dtype=np.float64), 1.0 if spacing is None else spacing


def _model(model):
    """A FittedModel, read from its file when ``model`` is a path."""
    if isinstance(model, (str, os.PathLike)):
        from roughgp.surface_models.model import FittedModel
        return FittedModel.load(model)
    return model


def read(path, *, kind="auto", spacing=None, channel=0, unit=None):
    """Read a profile or a surface from a file of any format read: text and CSV, ``.npy``,
    x-y-z lists, ``.x3p`` and instrument files (:data:`~roughgp.io.measurement.READ_FORMATS`
    and SurfaceTopography's).

    Returns a :class:`~roughgp.io.measurement.Measurement`: ``z`` in µm (``z[iy, ix]`` or
    ``z[ix]``, NaN where unmeasured), ``spacing`` in µm in array order, and where the spacing
    and the unit came from. The options are those of
    :func:`roughgp.io.measurement.read_measurement`: ``kind`` (``"auto"``, ``"profile"``,
    ``"surface"``), ``spacing`` (µm, overriding the file's), ``channel`` (of an instrument file),
    ``unit`` (of the heights, where the file states none or states it wrongly).
    """
    from roughgp.io.measurement import read_measurement
    return read_measurement(path, kind=kind, spacing=spacing, channel=channel, unit=unit)


def texture(surface, spacing=None, *, form="plane", s="auto", l="auto", degree=2, axis="auto",
            filtered=True, l_kind="gaussian"):
    """ISO texture parameters of a surface (ISO 25178-2) or a profile (ISO 4287 / 13565-2) after
    the F-operator (``form``: ``"plane"``, ``"polynomial"`` of ``degree``, ``"cylinder"`` along
    ``axis``, or None) and the S- and L-filters (nesting indices ``s``, ``l`` in µm, ``"auto"``
    for the standard's or None), unmeasured points handled.

    Returns a :class:`~roughgp.metrology.texture_report.TextureReport` (``.parameters``: ISO
    symbol -> value; ``.operators``, ``.notes``), from
    :func:`roughgp.metrology.texture_report.filtered_parameters` (``filtered=False``: the heights
    as read; ``l_kind``: ``"gaussian"``, ``"robust"`` or ``"stratified"``).
    """
    from roughgp.metrology.texture_report import filtered_parameters
    z, spacing = _heights(surface, spacing)
    return filtered_parameters(z, spacing, form=form, s=s, l=l, degree=degree, axis=axis,
                               filtered=filtered, l_kind=l_kind)


def fit(surface, spacing=None, *, model=None, form="plane", s=None, l=None, degree=2,
        axis="auto", marginal=None, seed=0, **options):
    """Fit a model to a measured surface or profile (holes allowed on a surface) and return it
    as a :class:`~roughgp.surface_models.model.FittedModel` (``.save(path)`` writes the model
    file; :func:`simulate`, :func:`check` and :func:`fill` use it).

    Args:
        surface: a Measurement or heights (µm, NaN where unmeasured).
        spacing: µm (default: the measurement's, or 1).
        model: a rung of the ladder (:data:`roughgp.surface_models.ladder.RUNGS`) for a surface:
            ``"eq18"`` (the default: the paper's eq 18 plus noise), ``"matern"``, ``"sm"`` (a
            2-D spectral mixture), ``"psd"`` (the measured PSD), or ``"auto"`` (the rung that
            predicts held-out points best, its heights' distribution chosen by the
            out-of-sample check, :func:`roughgp.checking.auto_choice.choose_checked`);
            ``"eq21"`` (the default) for a profile.
        form, degree, axis, s, l: the measurement's F-operator and S- and L-filters (default:
            a least-squares plane, no filter); the model describes the heights after F, and its
            simulations go through the rest of the chain as the measurement did.
        marginal: the heights' distribution, ``"gaussian"``, ``"johnson"`` or ``"iaaft"``
            (surfaces); None (the default): Gaussian, but chosen by ``model="auto"``.
        seed: of the fit's blocks or starts.
        options: passed on: ``block``, ``n_blocks``, ``nu``, ``data`` to
            :func:`~roughgp.surface_models.ladder.fit_rung` (a surface), ``num_mixtures``,
            ``n_candidates``, ``non_gaussian``, ``data`` to
            :func:`~roughgp.surface_models.fit.fit_profile_model` (a profile).
    """
    z, spacing = _heights(surface, spacing)
    if getattr(z, "ndim", 2) == 1:
        if model not in (None, "eq21"):
            raise ValueError(f"a profile is fitted with model 'eq21', got {model!r}")
        if marginal not in (None, "gaussian"):
            raise ValueError("a profile's marginal is 'gaussian' (non_gaussian=True keeps its "
                             f"skewness and kurtosis), got {marginal!r}")
        from roughgp.surface_models.fit import fit_profile_model
        return fit_profile_model(z, spacing, form=form, s=s, l=l, seed=seed, **options).model
    chain = dict(form=form, s=s, l=l, degree=degree, axis=axis, seed=seed)
    if model == "auto":
        from roughgp.checking.auto_choice import choose_checked
        return choose_checked(z, spacing, marginal=marginal, **chain, **options).model
    chain["marginal"] = marginal or "gaussian"
    from roughgp.surface_models.ladder import fit_rung
    return fit_rung("eq18" if model is None else model, z, spacing, **chain, **options)[0]


def simulate(model, shape, *, seed=None, spacing=None, n_samples=None, chain=False,
             predictive=None, fitted=None):
    """Draw new surfaces (or profiles) from a model.

    Args:
        model: a FittedModel or its file (drawn by
            :meth:`~roughgp.surface_models.model.FittedModel.simulate`), or one of
            :data:`PRESETS`: ``"ground"`` (eq 18 with figure 2's hyperparameters, noise variance
            1; :func:`roughgp.models.surfaces.ground`) or ``"honed"`` (figure 3's two honing
            steps; :func:`roughgp.models.surfaces.honed`).
        shape: ``(ny, nx)``, or ``n`` for a profile model.
        seed: int, None or a ``numpy.random.Generator``; the same seed gives the same draw.
        spacing: µm (default: the model's; 1 for a preset).
        n_samples: None (one draw of ``shape``) or an int (an array of that many; models only).
        chain: put the draw through the rest of the measurement's operator chain (its F-, S-
            and L-operators, :func:`roughgp.surface_models.chain.rest_of_chain`), as
            ``roughgp simulate --from`` does by default: heights like the measurement's
            texture heights (one draw only).
        predictive: None (the plug-in draws, all from ``model``) or how each draw's model is
            drawn first, the fit's uncertainty carried (a fitted model only):
            ``"refits"``, ``"sandwich"`` or ``"tiles"``
            (:func:`roughgp.checking.predictive.predictive_draws`).
        fitted: with ``predictive="tiles"``: ``(z, spacing)`` of the map (or part) the model
            was fitted on.
    """
    if isinstance(model, str) and model in PRESETS:
        if n_samples is not None or chain or predictive is not None:
            raise ValueError(f"the preset {model!r} draws one surface: n_samples, chain and "
                             f"predictive are for a fitted model")
        import dataclasses

        from roughgp.models import surfaces
        spacing = 1.0 if spacing is None else spacing
        if model == "ground":
            return surfaces.ground(shape, **dataclasses.asdict(surfaces.FIGURE_2),
                                   spacing=spacing, seed=seed)
        return surfaces.honed(shape, surfaces.FIGURE_3, spacing=spacing, seed=seed)
    model = _model(model)
    if predictive is None:
        if fitted is not None:
            raise ValueError("fitted is the map the tile bootstrap draws from: give it with "
                             "predictive='tiles'")
        z = model.simulate(shape, seed=seed, spacing=spacing, n_samples=n_samples)
    else:
        from roughgp.checking.predictive import predictive_draws
        z = predictive_draws(model, shape, source=predictive, seed=seed, spacing=spacing,
                             n_samples=n_samples, fitted=fitted)[0]
    if not chain:
        return z
    if n_samples is not None:
        raise ValueError("chain=True puts one draw through the chain: leave n_samples None")
    from roughgp.surface_models.chain import rest_of_chain
    return rest_of_chain(model, z, model.spacing if spacing is None else spacing).sl


def check(model, surface, spacing=None, *, n_simulations=19, seed=0, calibrate=None,
          **options):
    """Does the model reproduce the measurement? Its texture parameters placed among those of
    ``n_simulations`` draws of the model, put through the measurement's holes and the rest of
    its operator chain (:func:`roughgp.checking.model_check.check_model`).

    Returns a :class:`~roughgp.checking.model_check.ModelCheck` (``.outside``: the parameters
    outside the simulated range, a 2 / (n + 1) test; ``.parameters``: each with its rank), or,
    with ``calibrate=B``, a :class:`~roughgp.checking.calibrated.CalibratedCheck` calibrated by
    B refitted bootstrap copies (for a model fitted to this very measurement:
    :func:`roughgp.checking.calibrated.calibrated_check`). ``spacing`` defaults to the
    measurement's (the model's for an array); ``options``: ``names``, ``progress`` (called
    with ``(k, n)`` after each simulation, or after each bootstrap copy with ``calibrate``),
    and ``level`` of the calibrated check.
    """
    model = _model(model)
    if hasattr(surface, "z") and hasattr(surface, "spacing"):
        z, spacing = _heights(surface, spacing)
        if model.kind == "profile" and spacing is not None and len(spacing) == 2:
            spacing = (spacing[-1],)
    else:
        z = surface
    if calibrate is None:
        from roughgp.checking.model_check import check_model
        return check_model(model, z, spacing, n_simulations=n_simulations, seed=seed, **options)
    from roughgp.checking.calibrated import calibrated_check
    return calibrated_check(model, z, spacing, n_simulations=n_simulations,
                            n_bootstrap=calibrate, seed=seed, **options)


def fill(surface, spacing=None, *, model=None, **options):
    """Fill the unmeasured (NaN) points of a surface with the GP posterior: the form removed, eq
    18 fitted to the measured points (or ``model``'s kernel used), the points filled, the form
    added back (:func:`roughgp.filling.measured.fill_measured_surface`).

    Returns a :class:`~roughgp.filling.measured.MeasuredFill` (``.filled``: the measurement
    with its missing points filled; ``.sd``; ``.band``; ``.self_check``). ``options``:
    ``method`` (``"local"`` or ``"global"``), ``nu`` (0.5, 1.5, 2.5 or ``"auto"``),
    ``self_check``, ``seed``, ``form``, ``degree``, ``axis``, ``mask``, ... as
    :func:`~roughgp.filling.measured.fill_measured_surface` takes them.
    """
    from roughgp.filling.measured import fill_measured_surface
    z, spacing = _heights(surface, spacing)
    return fill_measured_surface(z, spacing=spacing, model=None if model is None else
                                 _model(model), **options)
