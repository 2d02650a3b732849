r"""Do the simulations with the measured heights (IAAFT) describe the part of a surface they
were not fitted on? Synthetic maps of known models, the measured-PSD model fitted on the left
half and checked on both halves (issue 40: the check of the IAAFT models;
``benchmarks/iaaft_held_out.py`` records the run, the chapter "Which model reproduces which
measurement" shows it).

Each case is a map of :data:`SHAPE` points of eq 18 with one of
:data:`~roughgp.experiments.check_calibration.CASES` (cycled), of one of :data:`KINDS`: its
Gaussian heights (``"gaussian"``), or their exponential, scaled to a log-sd of
:data:`LOG_SD` (``"lognormal"``: skewed heights, what the IAAFT heights are for). The
measured-PSD model (:func:`~roughgp.surface_models.fit.fit_psd_model`, the plane removed, no
filter) is fitted on the left half with each of :data:`MARGINALS` (the last two: the IAAFT
model's simulations drawn from bootstrap refits, the fit's uncertainty carried, and from the
tile bootstrap of the fitted half, :mod:`roughgp.checking.tile_bootstrap`) and checked with 19
simulations (:func:`~roughgp.checking.held_out.held_out_check`) on the left half it saw and on
the right half it did not. The map is one stationary surface, so a model that describes it
says "outside" in about 10 % of the cases per parameter on the right half (a little more: the
fit's own error is not carried). On the left half the model that copies the heights says it
less often: it has seen them. Two kinds more, maps whose halves differ (``"two-regions"``: two
regions of a population, ``"gradient"``: a roughness gradient across the map, both of
:func:`roughgp.experiments.held_out.synthetic_map`), are checked with the IAAFT heights, plug-in
and from the tile bootstrap (:data:`MARGINALS_OF`): there the check must go on saying
"outside" far more often than 10 %, or its wider simulations could no longer say no.

Before the IAAFT sample was drawn through the draw's own normal scores
(:mod:`roughgp.surface_models.iaaft`), on 20 maps of the ``stationary`` kind of
:mod:`roughgp.experiments.held_out` (the same models, a tilted plane added; not recorded), the
IAAFT simulations left 1.5 % of the parameters outside on the fitted half and 27.7 % on the
other, the Gaussian heights 7.7 % and 9.4 % on 18 of them; :func:`summary` gives the recorded
run's shares.
"""

from __future__ import annotations

import time
from pathlib import Path

import numpy as np

from roughgp.checking.held_out import held_out_check, part_of
from roughgp.checking.model_check import SURFACE_PARAMETERS
from roughgp.checking.predictive import predictive_models
from roughgp.checking.ranks import share_interval, verdict_within
from roughgp.checking.tile_bootstrap import tile_bootstrap_models
from roughgp.common.jsonl import read_records
from roughgp.experiments.check_calibration import CASES
from roughgp.experiments.held_out import eq18_model
from roughgp.experiments.real_out_of_sample import PASS
from roughgp.surface_models.fit import fit_psd_model

__all__ = ["KINDS", "DESCRIBED", "MARGINALS_OF", "MARGINALS", "SHAPE", "LOG_SD", "RECORDED",
           "synthetic_map",
           "PREDICTIVE", "iaaft_held_out_case", "load_records", "summary", "per_parameter"]

KINDS = ("gaussian", "lognormal", "two-regions", "gradient")
#: the kinds one stationary model describes (the check's level is judged on them); the others
#: are maps whose halves differ (:func:`~roughgp.experiments.held_out.synthetic_map`'s
#: ``hierarchical`` and ``gradient`` kinds: two regions of a population, a roughness gradient),
#: where a check must say "outside" more often, checked with the IAAFT heights alone
DESCRIBED = ("gaussian", "lognormal")
#: the heights of the simulations: Gaussian, IAAFT, IAAFT drawn from :data:`PREDICTIVE`
#: bootstrap refits of the fit (:func:`~roughgp.checking.predictive.predictive_models`), and
#: IAAFT drawn from 19 tile-bootstrap models of the fitted half (one per simulation,
#: :func:`~roughgp.checking.tile_bootstrap.tile_bootstrap_models`)
MARGINALS = ("gaussian", "iaaft", "iaaft-predictive", "iaaft-tiles")
#: the marginals run on each kind: all on the maps one model describes, the plug-in and the
#: tile bootstrap on the others (does the wider check still say no?)
MARGINALS_OF = {kind: MARGINALS if kind in DESCRIBED else
                ("iaaft", "iaaft-tiles") for kind in KINDS}
PREDICTIVE = 9
SHAPE = (128, 256)   #: the map; each half 128 x 128
LOG_SD = 0.6         #: the lognormal kind's log-sd (skewness about 2)
RECORDED = Path(__file__).resolve().parents[2] / "benchmarks" / "results" / \
    "iaaft_held_out.jsonl"


def synthetic_map(kind, index, *, shape=SHAPE, seed=0) -> np.ndarray:
    """The ``index``-th map of ``kind`` (module docstring), seeded by ``(seed, kind,
    index)``."""
    if kind not in KINDS:
        raise ValueError(f"kind must be one of {', '.join(KINDS)}, got {kind!r}")
    if kind not in DESCRIBED:
        from roughgp.experiments.held_out import synthetic_map as differing_halves
        return differing_halves("hierarchical" if kind == "two-regions" else kind, index,
                                shape=shape, seed=seed)[0]
    rng = np.random.default_rng([seed, KINDS.index(kind), index])
    variance, lam_a, lam_b, angle, noise = CASES[index % len(CASES)]
    z = eq18_model(variance, lam_a, lam_b, angle, noise).simulate(shape, seed=rng)
    if kind == "lognormal":
        z = np.exp(LOG_SD * z / np.sqrt(variance + noise))
    return z


def iaaft_held_out_case(kind, index, *, shape=SHAPE, seed=0, marginals=MARGINALS) -> dict:
    """One case (module docstring): per marginal of ``marginals``, the parameters outside on
    the fitted (left) and the held-out (right) half."""
    start = time.perf_counter()
    z = synthetic_map(kind, index, shape=shape, seed=seed)
    left = part_of(z.shape, "left")
    checks, fitted = {}, {}
    for marginal in marginals:
        heights = marginal.split("-")[0]   # the predictive variants draw from the IAAFT fit
        if heights not in fitted:
            fitted[heights] = fit_psd_model(left.cut(z), 1.0, marginal=heights, s=None, l=None,
                                            seed=seed).model
        model = fitted[heights]
        models = None
        if marginal == "iaaft-predictive":
            models = predictive_models(model, PREDICTIVE, source="refits", seed=index)[0]
        elif marginal == "iaaft-tiles":
            models = tile_bootstrap_models(model, left.cut(z), 19, seed=index)
        both = held_out_check(model, z, (1.0, 1.0), fitted_part=left, seed=1000 + index,
                              models=models)
        checks[marginal] = {"fitted": list(both.fitted.outside),
                            "held_out": list(both.held_out.outside)}
    return {"kind": kind, "index": int(index), "seed": int(seed), "shape": list(shape),
            "checks": checks, "seconds": time.perf_counter() - start}


def load_records(path=RECORDED) -> list:
    """The recorded cases (none when the file does not exist), the lines of one case (its
    kind, index and seed: a marginal added to the run later is a line of its own) merged:
    their checks together, their seconds summed."""
    merged: dict = {}
    for record in read_records(path):
        key = (record["kind"], record["index"], record["seed"])
        if key in merged:
            merged[key]["checks"].update(record["checks"])
            merged[key]["seconds"] += record["seconds"]
        else:
            merged[key] = {**record, "checks": dict(record["checks"])}
    return list(merged.values())


def _outside_sets(records, kind, marginal, half) -> list:
    """The parameters outside on ``half``, one set per case of ``kind`` checked with
    ``marginal``."""
    return [set(r["checks"][marginal][half]) for r in records
            if r["kind"] == kind and marginal in r["checks"]]


def summary(records) -> "pandas.DataFrame":
    """Per kind, marginal and half: the cases, the share of the parameters outside (the mean of
    each case's share of the 13) with its 95 % interval (the cases independent,
    :func:`~roughgp.checking.ranks.share_interval`) and its verdict against 10 % +- 3 %
    (:func:`~roughgp.checking.ranks.verdict_within`), Sq's share with its interval, and the
    share of the cases with at most :data:`~roughgp.experiments.real_out_of_sample.PASS` of the
    13 outside and its 95 % upper bound (the real maps' "reproduced"; a check at its level
    would pass about :func:`~roughgp.checking.ranks.pass_chance` of them)."""
    import pandas as pd
    lines = []
    for kind in KINDS:
        rows = [r for r in records if r["kind"] == kind]
        if not rows:
            continue
        for marginal in MARGINALS:
            for half in ("fitted", "held_out"):
                outside = _outside_sets(rows, kind, marginal, half)
                if not outside:
                    continue
                mean = [len(o) / len(SURFACE_PARAMETERS) for o in outside]
                share, low, high = share_interval(mean)
                sq, sq_low, sq_high = share_interval(["Sq" in o for o in outside])
                passed, _, passed_high = share_interval([len(o) <= PASS for o in outside])
                lines.append({"kind": kind, "heights": marginal, "half": half.replace("_", "-"),
                              "cases": len(outside), "outside (mean of 13)": share,
                              "95 % low": low, "95 % high": high,
                              "within 10 % ± 3 %": verdict_within(low, high),
                              "Sq outside": sq, "Sq 95 % interval": f"{sq_low:.2f}-{sq_high:.2f}",
                              f"≤ {PASS} outside": passed,
                              f"≤ {PASS} outside, 95 % high": passed_high})
    return pd.DataFrame(lines)


def per_parameter(records, half="held_out") -> "pandas.DataFrame":
    """Per kind one model describes (:data:`DESCRIBED`) and marginal, on ``half``
    (``"fitted"`` or ``"held_out"``): the cases and, per parameter of
    :data:`~roughgp.checking.model_check.SURFACE_PARAMETERS`, the share of the cases with it
    outside, its 95 % interval and its verdict against 10 % +- 3 %, as ``"15% [11%, 20%] ?"``
    (``yes``, ``no``, ``?`` undecided: :func:`~roughgp.checking.ranks.verdict_within`)."""
    import pandas as pd
    if half not in ("fitted", "held_out"):
        raise ValueError(f"half must be 'fitted' or 'held_out', got {half!r}")
    mark = {"yes": "yes", "no": "no", "undecided": "?"}
    lines = []
    for kind in DESCRIBED:
        for marginal in MARGINALS:
            outside = _outside_sets(records, kind, marginal, half)
            if len(outside) < 2:
                continue
            line = {"kind": kind, "heights": marginal, "cases": len(outside)}
            for name in SURFACE_PARAMETERS:
                share, low, high = share_interval([name in o for o in outside])
                line[name] = (f"{100 * share:.0f}% [{100 * low:.0f}%, {100 * high:.0f}%] "
                              f"{mark[verdict_within(low, high)]}")
            lines.append(line)
    return pd.DataFrame(lines)
