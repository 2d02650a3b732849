r"""Figure 7 repaired: the turned surface as a deterministic feed mark plus Gaussian processes
(beyond the paper; issue 41, the remedy section 3.4 names: "hierarchical GPs [36]").

The paper's eq 22 draws turned surfaces that lose the periodicity and gain short wavelengths
(:mod:`roughgp.experiments.turned_surface`). Here the same synthetic surface (figure 6's
stand-in, levelled by the F-operator) is fitted with the ``periodic-mark`` rung
(:func:`roughgp.surface_models.periodic_model.fit_periodic_model`: the mark folded at the
fitted feed, each mark's shift and depth Gaussian from mark to mark, eq 18 on the rest) and
its draws are measured like eq 22's: the periodicity at 1 .. 5 feeds and the share of
wavelengths below an eighth of a feed, against the data and against the data's two halves
(rows), and the model check of the 13 areal parameters
(:func:`roughgp.checking.model_check.check_model`).

:func:`repair_shown` is the one judgement the chapter "Turned surfaces" and the ledger share:
the draws show neither flaw (:func:`~roughgp.experiments.turned_surface.flaw_shown`'s
thresholds, those by which eq 22 shows both), the data's two measures lie within
:data:`SPREAD` standard deviations of the draws' mean, and the check leaves at most
:data:`MAX_OUTSIDE` of its 13 parameters outside.

The same for the turned profile of figures 4 and 5 (:func:`repaired_figure5`): the
``periodic-mark-profile`` rung fitted to the raw profile (the F-operator a line), its draws'
ISO 4287 parameters and dale share against the data's as the chapter "Turned profiles" compares
eq 21's (:func:`roughgp.experiments.turned_profile.figure5_simulations`), and the model check of
the 11 profile parameters.
"""

from __future__ import annotations

import dataclasses
import functools
import json
import time
from pathlib import Path

import numpy as np

from roughgp.checking.model_check import ModelCheck, check_model
from roughgp.common.results_cache import persistent
from roughgp.experiments import turned_profile as tp
from roughgp.experiments import turned_surface as ts
from roughgp.metrology import levelling
from roughgp.models import turned
from roughgp.surface_models.periodic_model import (
    PeriodicModelFit,
    fit_periodic_model,
    fit_periodic_profile,
)

__all__ = ["SPREAD", "MAX_OUTSIDE", "N_CHECK", "RepairedFigure7", "fit_mark_model",
           "RepairedFigure5", "repaired_figure5",
           "repaired_figure7", "repair_shown", "within_spread", "surface_record", "RECORDED",
           "load_records", "records_table", "summarise_records"]

#: the data's measures must lie within this many sd of the draws' mean
SPREAD = 2.0
#: the model check's most parameters outside of 13 (the issue's "at most 2 of 13")
MAX_OUTSIDE = 2
#: simulations of the model check (a 10 % chance per parameter for a model that describes it)
N_CHECK = 19


@dataclasses.dataclass(frozen=True)
class RepairedFigure7:
    """The periodic-mark model on figure 6's stand-in.

    Attributes:
        fit: the fit (:class:`~roughgp.surface_models.periodic_model.PeriodicModelFit`).
        data, halves, draws: the flaw measures of the levelled data, of its two halves (rows
            0 .. ny/2 and ny/2 .. ny) and of the model's levelled draws
            (:class:`~roughgp.experiments.turned_surface.FlawMeasure`).
        check: the model check on the data (:data:`N_CHECK` simulations).
        n_sim: draws measured.
    """

    fit: PeriodicModelFit
    data: ts.FlawMeasure
    halves: ts.FlawMeasure
    draws: ts.FlawMeasure
    check: ModelCheck
    n_sim: int

    @property
    def outside(self) -> list:
        """The check's parameters outside the simulations' range."""
        return [p.name for p in self.check.parameters if p.outside]


def _raw(shape, seed):
    return turned.turned_surface(shape, ts.SPACING, ts.PARAMS, seed=seed)


@functools.lru_cache(maxsize=2)
@persistent
def _fit(shape, seed):
    return fit_periodic_model(_raw(shape, seed), ts.SPACING, form="plane")


def fit_mark_model(shape=ts.SHAPE, seed=ts.SEED) -> PeriodicModelFit:
    """The periodic-mark model fitted to figure 6's stand-in (the turned surface of
    :mod:`roughgp.experiments.turned_surface`, the F-operator a plane, no filter); cached."""
    return _fit((int(shape[0]), int(shape[1])), int(seed))


@functools.lru_cache(maxsize=2)
def _repaired(shape, seed, n_sim, n_check):
    fit = _fit(shape, seed)
    raw = _raw(shape, seed)
    z = levelling.level(raw, spacing=ts.SPACING)
    feed = ts.PARAMS.feed
    half = shape[0] // 2
    data = ts.measure_flaw([z], feed, ts.SPACING)
    halves = ts.measure_flaw([z[:half], z[half:]], feed, ts.SPACING)
    draws = fit.model.simulate(shape, seed=seed + 1, n_samples=n_sim)
    measured = ts.measure_flaw([levelling.level(d, spacing=ts.SPACING) for d in draws], feed,
                               ts.SPACING)
    check = check_model(fit.model, raw, ts.SPACING, n_simulations=n_check, seed=seed + 2)
    return RepairedFigure7(fit, data, halves, measured, check, n_sim)


def repaired_figure7(full=None, *, shape=ts.SHAPE, seed=ts.SEED, n_sim=None,
                     n_check=N_CHECK) -> RepairedFigure7:
    """Fit, draw and measure (module docstring). ``n_sim``: draws measured (default as eq 22's,
    :func:`~roughgp.experiments.turned_surface.n_simulations`); draws seeded by ``seed + 1``,
    the check by ``seed + 2``. Cached."""
    n = ts.n_simulations(full) if n_sim is None else int(n_sim)
    return _repaired((int(shape[0]), int(shape[1])), int(seed), n, int(n_check))


def within_spread(draws: ts.FlawMeasure, data: ts.FlawMeasure) -> tuple[bool, bool]:
    """``(periodicity, short_share)``: whether the data's periodicity at the last feed and its
    short-wavelength share lie within :data:`SPREAD` standard deviations (over the draws) of
    the draws' mean."""
    per = draws.periodicity[:, -1]
    short = draws.short_share
    return (bool(abs(data.mean_periodicity[-1] - per.mean()) <= SPREAD * per.std(ddof=1)),
            bool(abs(data.mean_short_share - short.mean()) <= SPREAD * short.std(ddof=1)))


def repair_shown(result: RepairedFigure7) -> bool:
    """The model repairs figure 7 (module docstring): no flaw, the data within the draws'
    spread, at most :data:`MAX_OUTSIDE` parameters outside."""
    no_flaw = ts.flaw_shown(result.draws, result.data) == (False, False)
    return bool(no_flaw and all(within_spread(result.draws, result.data))
                and len(result.outside) <= MAX_OUTSIDE)


#: a run of :func:`surface_record` over turned surfaces of several seeds
#: (``benchmarks/turned_repair.py``)
RECORDED = (Path(__file__).resolve().parents[2] / "benchmarks" / "results"
            / "turned_repair.jsonl")


def surface_record(seed, shape=ts.SHAPE, n_sim=None) -> dict:
    """What the recorded run keeps of :func:`repaired_figure7` on the turned surface of
    ``seed``: the fit's seconds and feed, the flaw measures (data and draws), the judgements
    and the check's ranks."""
    start = time.perf_counter()
    fit = fit_mark_model(shape, seed)
    fit_seconds = time.perf_counter() - start
    r = repaired_figure7(False, shape=shape, seed=seed, n_sim=n_sim)
    per, short = within_spread(r.draws, r.data)
    return {"seed": int(seed), "shape": list(shape), "n_sim": r.n_sim,
            "fit_seconds": round(fit_seconds, 2), "feed_um": fit.model.hyperparameters["feed_um"],
            "data_periodicity": float(r.data.mean_periodicity[-1]),
            "draws_periodicity": float(r.draws.mean_periodicity[-1]),
            "draws_periodicity_sd": float(r.draws.periodicity[:, -1].std(ddof=1)),
            "data_short_share": r.data.mean_short_share,
            "draws_short_share": r.draws.mean_short_share,
            "draws_short_share_sd": float(r.draws.short_share.std(ddof=1)),
            "flaw": list(ts.flaw_shown(r.draws, r.data)), "within": [per, short],
            "outside": r.outside,
            "ranks": {p.name: int(p.rank) for p in r.check.parameters},
            "seconds": round(time.perf_counter() - start, 2)}


def load_records(path=RECORDED) -> list:
    """The recorded run's records (an empty list where there is none)."""
    path = Path(path)
    if not path.is_file():
        return []
    return [json.loads(line) for line in path.read_text().splitlines() if line.strip()]


def summarise_records(records) -> dict:
    """Over the recorded surfaces: how many, with no flaw, with the data within the draws'
    spread (both measures), with at most :data:`MAX_OUTSIDE` outside, the largest count
    outside, how often each parameter was outside, and the slowest fit (s)."""
    records = list(records)
    if not records:
        raise ValueError("records must hold at least one surface_record")
    counts: dict = {}
    for r in records:
        for name in r["outside"]:
            counts[name] = counts.get(name, 0) + 1
    return {"n": len(records),
            "no_flaw": sum(not any(r["flaw"]) for r in records),
            "within": sum(all(r["within"]) for r in records),
            "passed": sum(len(r["outside"]) <= MAX_OUTSIDE for r in records),
            "most_outside": max(len(r["outside"]) for r in records),
            "outside_counts": dict(sorted(counts.items(), key=lambda kv: -kv[1])),
            "slowest_fit": max(r["fit_seconds"] for r in records)}


def records_table(records):
    """The records as a table for a page (a pandas ``Styler``): per surface the periodicity at
    five feeds and the short-wavelength share of the data and the draws, and the check's
    parameters outside."""
    import pandas as pd

    rows = {}
    for r in sorted(records, key=lambda r: r["seed"]):
        rows[r["seed"]] = {
            ("periodicity at 5 feeds", "data"): r["data_periodicity"],
            ("periodicity at 5 feeds", "draws"): f"{r['draws_periodicity']:.3f} ± "
                                                 f"{r['draws_periodicity_sd']:.3f}",
            ("short share (1e-3)", "data"): 1e3 * r["data_short_share"],
            ("short share (1e-3)", "draws"): f"{1e3 * r['draws_short_share']:.2f} ± "
                                             f"{1e3 * r['draws_short_share_sd']:.2f}",
            ("model check", "outside"): ", ".join(r["outside"]) or "none"}
    table = pd.DataFrame.from_dict(rows, orient="index")
    table.columns = pd.MultiIndex.from_tuples(table.columns)
    table.index.name = "seed"
    formats = {("periodicity at 5 feeds", "data"): "{:.3f}",
               ("short share (1e-3)", "data"): "{:.2f}"}
    return table.style.format(formats).set_caption(
        f"the periodic-mark model on {len(table)} turned surfaces (draws: mean ± sd)")


@dataclasses.dataclass(frozen=True)
class RepairedFigure5:
    """The periodic-mark-profile model on figure 4's stand-in: the fit, its draws and their
    parameters (:class:`~roughgp.experiments.turned_profile.TurnedProfileSimulations`: the
    draws levelled as the data), and the model check of the raw profile."""

    fit: PeriodicModelFit
    simulations: tp.TurnedProfileSimulations
    check: ModelCheck

    @property
    def outside(self) -> list:
        return [p.name for p in self.check.parameters if p.outside]


@functools.lru_cache(maxsize=1)
def _repaired_profile(n_points, n_sim, n_check):
    result = tp.figure5_fit(n_points)
    fit = fit_periodic_profile(np.asarray(result.raw), result.spacing, form="plane")
    seed = result.seed + 1
    draws = fit.model.simulate(result.n_points, seed=seed, n_samples=n_sim)
    each = [tp.profile_values(levelling.level(d, spacing=result.spacing), result.spacing)
            for d in draws]
    values = {key: np.array([v[key] for v in each]) for key in tp.PARAMETER_KEYS}
    ranges = {key: tuple(float(b) for b in np.nanpercentile(v, [2.5, 97.5]))
              for key, v in values.items()}
    inside = {key: bool(lo <= result.measured[key] <= hi) for key, (lo, hi) in ranges.items()}
    sims = tp.TurnedProfileSimulations(seed, draws, values, dict(result.measured), ranges,
                                       inside)
    check = check_model(fit.model, np.asarray(result.raw), result.spacing,
                        n_simulations=n_check, seed=seed + 1)
    return RepairedFigure5(fit, sims, check)


def repaired_figure5(n_points=tp.N_POINTS, n_sim=40, n_check=N_CHECK) -> RepairedFigure5:
    """Fit the periodic-mark-profile model to the profile of ``n_points`` of
    :func:`~roughgp.experiments.turned_profile.figure5_fit`, draw ``n_sim`` profiles (seeded by
    the fit's seed + 1) and check it (seed + 2). Cached."""
    return _repaired_profile(int(n_points), int(n_sim), int(n_check))
