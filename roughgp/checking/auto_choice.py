r"""``--model auto`` by the held-out prediction and the out-of-sample check together (beyond the
paper; issue 40, item 5).

The ladder (:func:`roughgp.surface_models.ladder.choose_model`) chooses the covariance: the
rung that predicts held-out measured points best by kriging, the simplest within one standard
error. Kriging rates the covariance at short lags and says nothing of the heights'
distribution, and a model that predicts the holes well can still draw surfaces unlike the
measured one (the real maps of ``data/``: eq 18 with Gaussian heights leaves 9 to 13 of 13
texture parameters outside on the very crop it was fitted on,
``benchmarks/results/real_out_of_sample.md``). So :func:`choose_checked` asks the second
question of the rung chosen: fitted on one half of the map with each height distribution
(:data:`~roughgp.surface_models.chain.MARGINALS`: Gaussian, Johnson's four moments, IAAFT's
whole distribution), which one's simulations reproduce the texture parameters of the *other*
half, which the fit did not see (:func:`~roughgp.checking.model_check.check_model`, 19
simulations: a parameter outside with probability 1/10 for a model that describes the
surface)? It keeps the distribution with the fewest parameters outside there, the simpler one
on a tie (Gaussian, then Johnson, then IAAFT), fits that on all the measured points and says
why, with the count of each.

The halves are those of the map's central window of at most :data:`LONG` points along its
longer axis and :data:`SHORT` across (:func:`central_window`), halved along the longer axis, so
the check's cost is bounded whatever the map's size. A height distribution given by the
caller is not chosen but still checked, and its out-of-sample count is reported. A map too
small to halve (fewer than :data:`~roughgp.checking.held_out.MIN_PART` points per half along
either axis) keeps the given distribution (Gaussian by default) and says so.
"""

from __future__ import annotations

import dataclasses
import time

import numpy as np

from roughgp.checking.held_out import MIN_PART, Part, part_of
from roughgp.checking.model_check import check_model
from roughgp.common.checks import check_integer, surface_array
from roughgp.common.grid import normalize
from roughgp.surface_models.chain import MARGINALS
from roughgp.surface_models.ladder import LadderChoice, choose_model, fit_rung
from roughgp.surface_models.model import FittedModel

__all__ = ["LONG", "SHORT", "N_SIMULATIONS", "HeightsCandidate", "CheckedChoice",
           "central_window", "check_halves", "choose_checked"]

LONG, SHORT = 512, 256  #: the window of the check: at most 512 points along, 256 across
N_SIMULATIONS = 19  #: the check's simulations (a parameter outside with probability 1/10)


def central_window(shape, long=LONG, short=SHORT) -> tuple:
    """``(first row, first column, rows, columns, half)``: the central window of a map of
    ``shape`` (at most ``long`` points along its longer axis, ``short`` across) and the half
    of it to fit, ``"left"`` when the window is at least as wide as tall, else ``"top"``."""
    ny, nx = (int(n) for n in shape)
    wide = nx >= ny
    rows, cols = (min(ny, short), min(nx, long)) if wide else (min(ny, long), min(nx, short))
    return (ny - rows) // 2, (nx - cols) // 2, rows, cols, ("left" if wide else "top")


@dataclasses.dataclass(frozen=True)
class HeightsCandidate:
    """One height distribution of the chosen rung, fitted on one half and checked on the other.

    Attributes:
        marginal: ``"gaussian"``, ``"johnson"`` or ``"iaaft"``.
        outside: the texture parameters outside the simulations' range on the held-out half
            (empty: none); None when refused.
        refused: why the fit or the check could not be made there (None: it was).
        seconds: the fit and the check.
    """

    marginal: str
    outside: tuple | None
    refused: str | None
    seconds: float


@dataclasses.dataclass(frozen=True)
class CheckedChoice:
    """What :func:`choose_checked` returns.

    Attributes:
        ladder: the held-out prediction's choice of the rung (every rung scored).
        candidates: each height distribution checked out of sample (empty: the map is too
            small to halve).
        marginal: the height distribution chosen.
        reason: why, in one sentence (counts included).
        model: the rung with that distribution, fitted on all the measured points.
        fitted_part, held_out_part: the halves of the check (None where none was made).
        n_simulations: the check's simulations.
    """

    ladder: LadderChoice
    candidates: tuple
    marginal: str
    reason: str
    model: FittedModel
    fitted_part: Part | None
    held_out_part: Part | None
    n_simulations: int

    @property
    def chosen(self) -> str:
        return self.ladder.chosen

    @property
    def range_notes(self) -> tuple:
        return self.ladder.range_notes


def check_halves(shape) -> tuple:
    """The fitted and the held-out :class:`~roughgp.checking.held_out.Part` of a map of
    ``shape``: the halves of its :func:`central_window`, or ``(None, None)`` where a half
    would be smaller than :data:`~roughgp.checking.held_out.MIN_PART`."""
    r0, c0, rows, cols, half = central_window(shape)
    if half == "left":
        mid = c0 + cols // 2
        specs = (f"{r0}:{r0 + rows},{c0}:{mid}", f"{r0}:{r0 + rows},{mid}:{c0 + cols}")
    else:
        mid = r0 + rows // 2
        specs = (f"{r0}:{mid},{c0}:{c0 + cols}", f"{mid}:{r0 + rows},{c0}:{c0 + cols}")
    try:
        return tuple(part_of(shape, spec) for spec in specs)
    except ValueError:
        return None, None


def choose_checked(z, spacing=1.0, *, marginal=None, n_simulations=N_SIMULATIONS, seed=0,
                   progress=None, on_rung=None, on_check=None, **settings) -> CheckedChoice:
    """The ladder's rung by held-out prediction, its height distribution by the out-of-sample
    check (module docstring).

    Args:
        z: the measured heights, NaN where unmeasured.
        spacing: µm, one number or ``(dy, dx)``.
        marginal: None (choose among :data:`~roughgp.surface_models.chain.MARGINALS`) or one
            of them (kept, and checked).
        n_simulations: the check's simulations, an integer in [9, 999].
        seed: of the fits and the check's simulations.
        progress: called with each rung as the ladder scores it.
        on_rung: called with the ladder's :class:`~roughgp.surface_models.ladder.LadderChoice`
            once it has chosen.
        on_check: called with each :class:`HeightsCandidate` as it is checked.
        settings: the ladder's (:func:`~roughgp.surface_models.ladder.choose_model`): the
            operators ``form``, ``s``, ``l``, ``degree``, ``axis``; ``rungs``, ``block``,
            ``n_blocks``, ``nu``, ``data``, ``likelihood``.

    Raises:
        ValueError: a ``marginal`` not among them, ``n_simulations`` out of range, or what
            :func:`~roughgp.surface_models.ladder.choose_model` refuses.
    """
    if marginal is not None and marginal not in MARGINALS:
        raise ValueError(f"marginal must be None (chosen) or one of {list(MARGINALS)}, got "
                         f"{marginal!r}")
    n_simulations = check_integer("n_simulations", n_simulations, 9, 999)
    arr = surface_array(z)
    _, steps = normalize(arr.shape, spacing)
    ladder = choose_model(arr, steps, marginal=marginal or "gaussian", seed=seed,
                          progress=progress, **settings)
    if on_rung is not None:
        on_rung(ladder)
    fit_settings = {k: v for k, v in settings.items() if k != "rungs"}
    fitted_part, held_out_part = check_halves(arr.shape)
    if fitted_part is None:
        kept = marginal or "gaussian"
        reason = (f"{'given' if marginal else 'the default'}: the map ({arr.shape[0]} x "
                  f"{arr.shape[1]} points) is too "
                  f"small to fit one half and check the other (each half needs at least "
                  f"{MIN_PART} points along each axis)")
        return CheckedChoice(ladder, (), kept, reason,
                             _noted(ladder.model, kept, reason, ()), None, None, n_simulations)
    za, zb = fitted_part.cut(arr), held_out_part.cut(arr)
    candidates = []
    for name in ((marginal,) if marginal else MARGINALS):
        start = time.perf_counter()
        try:
            model, _ = fit_rung(ladder.chosen, za, steps, marginal=name, seed=seed,
                                **fit_settings)
            check = check_model(model, zb, steps, n_simulations=n_simulations, seed=seed)
            found = HeightsCandidate(name, tuple(check.outside), None,
                                     time.perf_counter() - start)
        except (ValueError, np.linalg.LinAlgError) as error:
            found = HeightsCandidate(name, None, str(error).splitlines()[0],
                                     time.perf_counter() - start)
        candidates.append(found)
        if on_check is not None:
            on_check(found)
    checked = [c for c in candidates if c.outside is not None]
    where = (f"fitted on rows {fitted_part.rows[0]}:{fitted_part.rows[1]}, columns "
             f"{fitted_part.cols[0]}:{fitted_part.cols[1]}, checked on rows "
             f"{held_out_part.rows[0]}:{held_out_part.rows[1]}, columns "
             f"{held_out_part.cols[0]}:{held_out_part.cols[1]} with {n_simulations} "
             f"simulations")
    if not checked:
        kept = marginal or "gaussian"
        reason = (f"{'given' if marginal else 'the default'}: no height distribution could "
                  f"be checked out of sample "
                  f"({where}; " + "; ".join(f"{c.marginal}: {c.refused}" for c in candidates)
                  + ")")
        return CheckedChoice(ladder, tuple(candidates), kept, reason,
                             _noted(ladder.model, kept, reason, candidates), fitted_part,
                             held_out_part, n_simulations)
    best = min(checked, key=lambda c: (len(c.outside), MARGINALS.index(c.marginal)))
    counts = "; ".join(f"{c.marginal} {len(c.outside)}" if c.outside is not None else
                       f"{c.marginal} refused" for c in candidates)
    if marginal:
        reason = (f"given; {len(best.outside)} of the texture parameters outside the "
                  f"simulations' range on the half the fit did not see ({where})")
    else:
        reason = (f"they leave the fewest texture parameters outside the simulations' range "
                  f"on the half the fit did not see ({counts}; {where}; the simpler "
                  f"distribution on a tie)")
    model = ladder.model
    if best.marginal != (marginal or "gaussian"):
        model, _ = fit_rung(ladder.chosen, arr, steps, marginal=best.marginal, seed=seed,
                            **fit_settings)
        chosen_by = {k: v for k, v in ladder.model.fit.items()    # the ladder's own record
                     if k in ("chosen_by", "held_out_rmse_um", "refused_rungs")}
        model = dataclasses.replace(model, fit={**model.fit, **chosen_by})
    return CheckedChoice(ladder, tuple(candidates), best.marginal, reason,
                         _noted(model, best.marginal, reason, candidates), fitted_part,
                         held_out_part, n_simulations)


def _noted(model, marginal, reason, candidates):
    """``model`` with the heights' choice in its ``fit`` (the model file keeps it)."""
    outside = {c.marginal: (None if c.outside is None else len(c.outside)) for c in candidates}
    return dataclasses.replace(model, fit={**model.fit,
                                           "heights_chosen_by": f"{marginal} heights: {reason}",
                                           "out_of_sample_outside": outside})
