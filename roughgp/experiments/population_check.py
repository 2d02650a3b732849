r"""Does the population model describe a region it never saw? Synthetic parts of known
populations (beyond the paper; issue 40, item 3; ``benchmarks/population_check.py`` records
the run, the chapter "Does the model check say no when it should?" shows it).

Each case draws :data:`REGIONS` ``+ 1`` regions of one part, each a 64 x 64 map (eq 18 with one
of :data:`~roughgp.experiments.check_calibration.CASES`, cycled; a tilted plane added):

- ``"alike"``: every region the same eq 18: one stationary model describes them all;
- ``"hierarchical"``: each region's variance times :math:`e^{0.4 g}` and each length times
  :math:`e^{0.25 g'}` (:math:`g, g'` standard normal per region), the population of the
  out-of-sample calibration's ``hierarchical`` kind (:mod:`roughgp.experiments.held_out`).

The last region is the one never seen. It is checked
(:func:`~roughgp.checking.model_check.check_model`, 19 simulations) against (:data:`MODELS`):

- ``eq18-one``: eq 18 fitted on the first region alone (the debiased Whittle likelihood): what
  a user with one measurement has;
- ``eq18-pooled``: eq 18 fitted on the first :data:`REGIONS` regions side by side (one map of
  them all, each region's plane removed first, the Whittle likelihood): one stationary model of
  all the data;
- ``population``: the ``eq18-population`` model of the first :data:`REGIONS` regions
  (:func:`~roughgp.surface_models.population_model.fit_population_model`), each simulation its
  own region;
- ``truth``: the true model of the unseen region (the check's own level, 2 / 20 = 10 %).

A model that describes the part leaves about 10 % of the cases outside per parameter on the
unseen region; for ``alike`` every model should, for ``hierarchical`` only the population.
"""

from __future__ import annotations

import time
from pathlib import Path

import numpy as np

from roughgp.checking.model_check import SURFACE_PARAMETERS, check_model
from roughgp.common.jsonl import read_records
from roughgp.experiments.check_calibration import CASES
from roughgp.experiments.held_out import LENGTH_SPREAD, VARIANCE_SPREAD, eq18_model

__all__ = ["KINDS", "MODELS", "REGIONS", "SHAPE", "RECORDED", "part_regions",
           "population_case", "load_records", "outside_shares", "shares_markdown"]

KINDS = ("alike", "hierarchical")
MODELS = ("eq18-one", "eq18-pooled", "population", "truth")
REGIONS = 6         #: the regions fitted (the case draws one more, never seen)
SHAPE = (64, 64)    #: each region's map
#: the recorded run (``benchmarks/population_check.py``: one :func:`population_case` a line)
RECORDED = Path(__file__).resolve().parents[2] / "benchmarks" / "results" / \
    "population_check.jsonl"


def part_regions(kind, index, *, regions=REGIONS, shape=SHAPE, seed=0):
    """``(maps, truths)``: ``regions + 1`` maps of the ``index``-th part of ``kind`` (module
    docstring) and their true eq 18 models."""
    if kind not in KINDS:
        raise ValueError(f"kind must be one of {', '.join(KINDS)}, got {kind!r}")
    rng = np.random.default_rng([seed, KINDS.index(kind), index, 11])
    variance, lam_a, lam_b, angle, noise = CASES[index % len(CASES)]
    iy, ix = np.indices(shape)
    maps, truths = [], []
    for _ in range(regions + 1):
        g = rng.standard_normal(3) if kind == "hierarchical" else np.zeros(3)
        truth = eq18_model(variance * np.exp(VARIANCE_SPREAD * g[0]),
                            lam_a * np.exp(LENGTH_SPREAD * g[1]),
                            lam_b * np.exp(LENGTH_SPREAD * g[2]), angle, noise)
        maps.append(truth.simulate(shape, seed=rng) + 0.01 * ix - 0.02 * iy)
        truths.append(truth)
    return maps, truths


def _plane_removed(z):
    """``z`` less its least-squares plane (each region's own, before the regions are set side
    by side for one fit: their planes would otherwise make a sawtooth)."""
    iy, ix = np.indices(z.shape)
    design = np.column_stack([np.ones(z.size), ix.ravel(), iy.ravel()])
    coefficients = np.linalg.lstsq(design, z.ravel(), rcond=None)[0]
    return z - (design @ coefficients).reshape(z.shape)


def population_case(kind, index, *, regions=REGIONS, n_simulations=19, seed=0) -> dict:
    """One case (module docstring): the parameters outside on the unseen region per model, the
    population's fitted spreads, and the seconds taken."""
    from roughgp.surface_models.fit import fit_surface_model
    from roughgp.surface_models.population_model import fit_population_model
    began = time.perf_counter()
    maps, truths = part_regions(kind, index, regions=regions, seed=seed)
    unseen, fitted_maps = maps[-1], maps[:-1]
    fits = {"eq18-one": fit_surface_model(fitted_maps[0], 1.0, l=None, likelihood="whittle",
                                          seed=seed + index).model,
            "eq18-pooled": fit_surface_model(np.concatenate([_plane_removed(z) for z in
                                                             fitted_maps], axis=1), 1.0,
                                             l=None, likelihood="whittle",
                                             seed=seed + index).model,
            "population": fit_population_model(fitted_maps, 1.0, l=None, n_draws=20,
                                               seed=seed + index).model,
            "truth": truths[-1]}
    check_seed = int(np.random.default_rng([seed, index, 13]).integers(2**31))
    outside = {name: list(check_model(model, unseen, n_simulations=n_simulations,
                                      seed=check_seed).outside)
               for name, model in fits.items()}
    hp = fits["population"].hyperparameters
    return {"kind": kind, "index": int(index), "seed": int(seed), "regions": int(regions),
            "shape": list(SHAPE), "n_simulations": int(n_simulations), "outside": outside,
            "spreads": {k: float(v) for k, v in hp.items() if k.endswith("_sd")
                        or k.endswith("_sd_deg")},
            "seconds": round(time.perf_counter() - began, 2)}


def load_records(path=RECORDED) -> list:
    """The recorded cases (none when the file does not exist)."""
    return read_records(path) if Path(path).exists() else []


def outside_shares(records, kind, model, names=SURFACE_PARAMETERS) -> dict | None:
    """``{parameter: share of kind's cases with it outside}`` for ``model`` (None without
    records), with ``"mean"`` over ``names`` and ``"cases"``."""
    rows = [r for r in records if r["kind"] == kind and model in r["outside"]]
    if not rows:
        return None
    shares = {n: float(np.mean([n in r["outside"][model] for r in rows])) for n in names}
    return {**shares, "mean": float(np.mean(list(shares.values()))), "cases": len(rows)}


def shares_markdown(records, names=("Sq", "Sa", "Sk", "Sz", "Sal", "Str", "Std")) -> str:
    """A Markdown table of the records: per kind and model, the cases, the share outside
    averaged over the 13 parameters and for ``names``."""
    head = ["kind", "model", "cases", "mean of 13", *names]
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    for kind in KINDS:
        for model in MODELS:
            s = outside_shares(records, kind, model)
            if s is not None:
                lines.append(f"| {kind} | {model} | {s['cases']} | {s['mean']:.0%} | "
                             + " | ".join(f"{s[n]:.0%}" for n in names) + " |")
    return "\n".join(lines)
