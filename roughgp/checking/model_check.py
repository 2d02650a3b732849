r"""Does a fitted model reproduce the measurement? Texture parameters of simulations against
the measurement's (beyond the paper).

:func:`check_model` applies the model's operators (F, S, L) to the measurement, draws
``n_simulations`` seeded surfaces of the model on the measurement's grid and puts each through
the rest of the operator chain as the measurement went through it
(:func:`roughgp.surface_models.chain.rest_of_chain`: for a model of stage ``"form-removed"``, the
measurement's holes, the F-operator fitted to the remaining points, the S- and L-filters; like
is compared with like), computes the ISO 25178-2 (surface) or ISO 4287 / 13565-2 (profile)
parameters of each, and places the measurement in the simulated spread: its rank among the
simulations, and whether it lies outside their range. With ``n`` simulations a measurement
that the model describes exactly falls outside their range with probability ``2 / (n + 1)`` (a
two-sided rank test: 10 % for the default 19); for a model fitted to the measurement itself
the share and the ranks are measured in :mod:`roughgp.experiments.model_check` (eq 18 fitted
to 64 x 64 synthetic maps: about 10 % on average, but the measurement lies above the
simulations of Sq, Sa and Sal more often than below, the fit finding the variance and the
lengths a little short; Sq, Sa and Sk outside in under 7 % of the cases). A parameter outside
the range is evidence against the model, one inside is no proof for it.
:func:`roughgp.checking.calibrated.calibrated_check` calibrates the check for a
model fitted to the measurement, by refitted bootstrap copies (``roughgp check --calibrate``).

A measurement with holes: its height and material-ratio parameters are those of its measured
points, and the simulations are given the same holes; the spatial parameters (Sal, Str, Std)
need a complete grid, so they are computed, for the measurement and for each simulation alike,
with the holes set to the mean of the measured heights (stated in ``notes``). That biases Sal
and Str on both sides alike, so the comparison stays like with like; version 1 filled the
measurement alone by the model's posterior mean (smoother than any simulation); a fill of each
simulation as well made the test's four-simulation check of the bullet land take 328 s.
``Std`` is an angle modulo 180 degrees (a direction, not a number on a line). The measured and
the simulated values are placed in the half-turn centred on the axial mean of all ``n + 1``
of them (:func:`axial_frame`), a centre that treats every value alike, so that the rank test
keeps its 2 / (n + 1). Version 2 unwrapped the simulations to within 90 degrees of the
measured value itself; on an isotropic surface, whose directions spread over the whole
half-turn, that put the measurement in the middle of its simulations by construction, and the
check of Std never said "outside" (0 % of 110 synthetic isotropic measurements against their
true model, :mod:`roughgp.experiments.model_check`).
"""

from __future__ import annotations

import dataclasses

import numpy as np

from roughgp.common.checks import as_generator
from roughgp.metrology.texture import areal_parameters, profile_parameters
from roughgp.metrology.texture_report import unit_of
from roughgp.surface_models.chain import apply_operators, rest_of_chain
from roughgp.surface_models.model import FittedModel

__all__ = ["ModelCheck", "ParameterCheck", "check_model", "plot_model_check", "axial_frame",
           "SURFACE_PARAMETERS", "PROFILE_PARAMETERS", "STD_FRAME", "chain_parameters",
           "draw_models"]

SURFACE_PARAMETERS = ("Sq", "Sa", "Ssk", "Sku", "Sp", "Sv", "Sz", "Sk", "Spk", "Svk", "Sal",
                      "Str", "Std")
PROFILE_PARAMETERS = ("Rq", "Ra", "Rsk", "Rku", "Rp", "Rv", "Rt", "Rk", "Rpk", "Rvk", "RSm")
_SPATIAL = ("Sal", "Str", "Std", "RSm")
#: how Std is compared (:func:`axial_frame`), for records that keep Std's ranks
STD_FRAME = "pooled axial mean"


@dataclasses.dataclass(frozen=True)
class ParameterCheck:
    """One parameter: the measurement's value, the simulations' values, the verdict.

    Attributes:
        rank: simulations below the measured value (0 .. n); NaN values left out.
        outside: the measured value lies below every or above every simulated value.
    """

    name: str
    unit: str
    measured: float
    simulated: np.ndarray
    rank: int
    outside: bool

    @property
    def low(self) -> float:
        return float(np.nanmin(self.simulated)) if np.isfinite(self.simulated).any() else np.nan

    @property
    def high(self) -> float:
        return float(np.nanmax(self.simulated)) if np.isfinite(self.simulated).any() else np.nan

    @property
    def median(self) -> float:
        return float(np.nanmedian(self.simulated)) if np.isfinite(self.simulated).any() \
            else np.nan


@dataclasses.dataclass(frozen=True)
class ModelCheck:
    """What :func:`check_model` returns: one :class:`ParameterCheck` per parameter, the
    operators applied, notes, and the heights compared (measurement and first simulation)."""

    parameters: tuple
    n_simulations: int
    operators: tuple
    notes: tuple
    measured_heights: np.ndarray
    simulated_heights: np.ndarray

    @property
    def outside(self) -> list:
        """Names of the parameters whose measured value lies outside the simulated range."""
        return [p.name for p in self.parameters if p.outside]

    def to_dict(self) -> dict:
        return {"n_simulations": self.n_simulations, "operators": list(self.operators),
                "notes": list(self.notes), "outside": self.outside,
                "parameters": [{"name": p.name, "unit": p.unit, "measured": p.measured,
                                "simulated_min": p.low, "simulated_median": p.median,
                                "simulated_max": p.high, "rank": p.rank,
                                "outside": p.outside} for p in self.parameters]}


def _parameters(h, spacing, names, areal):
    if areal:
        values = areal_parameters(h, spacing=spacing, undefined="nan")
    else:
        values = profile_parameters(h, spacing=float(np.ravel(spacing)[-1]), undefined="nan")
    return {n: float(values.get(n, np.nan)) for n in names}


def _point_parameters(h, names, areal):
    """Height and material-ratio parameters of the finite points only (holes left out)."""
    from roughgp.metrology.texture_report import point_statistics
    values = point_statistics(h, areal)
    return {n: float(values[n]) for n in names if n in values}


def chain_parameters(heights, holes, spacing, names, areal, spatial):
    """The parameters ``names`` of ``heights`` (through the chain, NaN at ``holes``). With
    holes: the height parameters of the measured points, the ``spatial`` ones of the heights
    with their holes set to the measured points' mean (module docstring)."""
    if not holes.any():
        return _parameters(heights, spacing, names, areal)
    values = _point_parameters(heights, names, areal)
    if spatial:
        level = np.where(holes, np.nanmean(heights), heights)
        values.update(_parameters(level, spacing, spatial, areal))
    return {n: float(values.get(n, np.nan)) for n in names}


def axial_frame(simulated, measured):
    """The directions ``simulated`` (degrees, modulo 180) placed on a line for the rank test
    against the direction ``measured``: all of them, the measured one included, within 90
    degrees of their axial mean (the mean direction of the doubled angles; any direction when
    it is undefined), the whole frame shifted by a multiple of 180 degrees so that
    ``measured`` keeps its value. The centre depends on the ``n + 1`` values alike, so for a
    measurement drawn like the simulations each of them is equally likely to be the lowest or
    the highest (module docstring). Values that are not finite stay NaN; a measured value
    that is not finite leaves ``simulated`` as it is."""
    sims = np.asarray(simulated, dtype=np.float64)
    if not np.isfinite(measured):
        return sims
    pooled = np.append(sims[np.isfinite(sims)], measured)
    doubled = np.deg2rad(2.0 * pooled)
    centre = 0.5 * np.rad2deg(np.arctan2(np.sin(doubled).sum(), np.cos(doubled).sum()))

    def frame(angles):
        return centre + (np.asarray(angles) - centre + 90.0) % 180.0 - 90.0

    return frame(sims) + (measured - frame(measured))


def draw_models(model: FittedModel, models, n_simulations) -> list:
    """The model each of ``n_simulations`` draws comes from: ``model`` for every draw (the
    plug-in check), or ``models`` in turn (the predictive check: each a refit of a bootstrap
    copy, :func:`roughgp.checking.predictive.bootstrap_models`), repeated when fewer."""
    if models is None:
        return [model] * n_simulations
    models = list(models)
    if not models or any(not isinstance(m, FittedModel) or m.kind != model.kind for m in models):
        raise ValueError(f"models must be a non-empty sequence of {model.kind} FittedModels "
                         f"(the predictive draws), got {len(models)} item(s)")
    return [models[i % len(models)] for i in range(n_simulations)]


def check_model(model: FittedModel, z, spacing=None, *, n_simulations=19, seed=0,
                names=None, models=None, progress=None) -> ModelCheck:
    """Place the texture parameters of the measurement ``z`` among those of ``n_simulations``
    draws of ``model`` (module docstring).

    Args:
        model: a :class:`~roughgp.surface_models.model.FittedModel`.
        z: the measurement (``z[iy, ix]`` for a surface model, ``z[ix]`` for a profile model),
            um, NaN where unmeasured; the raw heights (the model's operators are applied here).
        spacing: of ``z`` (default: the model's).
        n_simulations: draws (>= 2; the default 19 makes "outside the range" a 10 % test).
        seed: of the draws; the same seed gives the same table.
        names: the parameters (default :data:`SURFACE_PARAMETERS` / :data:`PROFILE_PARAMETERS`).
        progress: None or a function called with ``(k, n_simulations)`` after each draw.
        models: None (every draw from ``model``: the plug-in check) or models to draw from in
            turn (the predictive check, :func:`draw_models`); ``model`` still gives the
            operators.
    """
    z = np.asarray(z, dtype=np.float64)
    areal = model.kind == "surface"
    if z.ndim != (2 if areal else 1):
        raise ValueError(f"a {model.kind} model is checked against a "
                         f"{'surface z[iy, ix]' if areal else 'profile z[ix]'}, got shape "
                         f"{z.shape}")
    if not isinstance(n_simulations, (int, np.integer)) or not 2 <= n_simulations <= 999:
        raise ValueError(f"n_simulations must be an integer in [2, 999], got {n_simulations!r}")
    spacing = model.spacing if spacing is None else spacing
    names = tuple(names or (SURFACE_PARAMETERS if areal else PROFILE_PARAMETERS))
    rng = as_generator(seed)
    notes = []
    measured_chain = apply_operators(z, spacing, model.cutoffs)
    heights = measured_chain.sl
    holes = ~np.isfinite(heights)
    spatial = [n for n in names if n in _SPATIAL] if holes.any() and areal else []
    measured = chain_parameters(heights, holes, spacing, names, areal, spatial)
    if holes.any():
        notes.append(f"{holes.mean():.1%} of the points unmeasured: the height parameters are "
                     f"of the measured points, the simulations given the same holes"
                     + (f"; {', '.join(spatial)} of the measurement and of each simulation "
                        f"with the holes set to the mean height" if spatial else ""))
    if model.stage == "filtered":
        notes.append("the model describes the heights after the filters (stage 'filtered'): "
                     "its simulations are compared as drawn, plane removed")
    sources = draw_models(model, models, n_simulations)
    if models is not None:
        notes.append(f"predictive simulations: drawn from {len(set(map(id, sources)))} models "
                     f"in turn (the fit's uncertainty carried), not from the one fitted model")
    simulated = {n: [] for n in names}
    first = None
    for k, source in enumerate(sources, start=1):
        draw = source.simulate(z.shape, seed=rng, spacing=spacing)
        h = rest_of_chain(model, draw, spacing, holes if holes.any() else None).sl
        values = chain_parameters(h, holes, spacing, names, areal, spatial)
        first = h if first is None else first
        for n in names:
            simulated[n].append(values[n])
        if progress is not None:
            progress(k, len(sources))
    checks = []
    for n in names:
        sims = np.asarray(simulated[n], dtype=np.float64)
        value = measured[n]
        if n == "Std":
            sims = axial_frame(sims, value)
            if (np.abs(sims[np.isfinite(sims)]) > 90.0).any():
                notes.append("Std is a direction modulo 180 deg: the simulated directions are "
                             "shown within 90 deg of the axial mean of all of them and the "
                             "measured one (beyond +-90 deg: the same directions, turned by "
                             "180 deg)")
        finite = sims[np.isfinite(sims)]
        rank = int(np.sum(finite < value))
        outside = bool(np.isfinite(value) and finite.size > 0
                       and (value < finite.min() or value > finite.max()))
        checks.append(ParameterCheck(n, unit_of(n), float(value), sims, rank, outside))
    return ModelCheck(tuple(checks), int(n_simulations), tuple(measured_chain.operators),
                      tuple(notes), heights, first)


def plot_model_check(check: ModelCheck, path=None, *, title=None):
    """One small panel per parameter: the simulated values (dots) and the measured value
    (a line; red when outside the simulated range). Returns the figure; saves it to ``path``
    when given."""
    import matplotlib.pyplot as plt

    from roughgp.common.plotting import use_style

    use_style()
    n = len(check.parameters)
    cols = min(n, 4)          # four panels a row: 7.6 in, the text >= 9 pt on the book's page
    rows = -(-n // cols)
    fig, axes = plt.subplots(rows, cols, figsize=(1.9 * cols, 2.0 * rows), squeeze=False)
    jitter = np.random.default_rng(0).uniform(-0.25, 0.25, check.n_simulations)
    for ax, p in zip(axes.flat, check.parameters):
        ax.plot(jitter, p.simulated, "o", ms=3, color="0.45", label="simulations")
        colour = "tab:red" if p.outside else "tab:blue"
        ax.axhline(p.measured, color=colour, lw=2, label="measurement")
        unit = p.unit.replace("um", "µm") if p.unit else ""
        ax.set_title(f"{p.name}" + (f" ({unit})" if unit else "")
                     + (" outside" if p.outside else ""), fontsize=11,
                     color=colour if p.outside else "black")
        ax.set_xlim(-1, 1)
        ax.set_xticks([])
        ax.ticklabel_format(axis="y", useOffset=False)   # 90.008, not +8.999e1 and 0.008
        if not np.isfinite(np.r_[p.simulated, p.measured]).any():
            ax.text(0.5, 0.5, "undefined\non these\nsurfaces", ha="center", va="center",
                    transform=ax.transAxes, fontsize=10, color="0.4")
            ax.set_yticks([])
        ax.tick_params(labelsize=11)
    for ax in list(axes.flat)[n:]:
        ax.set_visible(False)
    fig.suptitle(title or f"the measurement (line) among {check.n_simulations} simulations "
                 f"of the model (dots)", fontsize=11)
    if path is not None:
        fig.savefig(path, dpi=120, bbox_inches="tight")
    return fig
