r"""Is the out-of-sample check calibrated? Synthetic maps of known models, a model fitted on
the left half and checked on the right (issue 40; ``benchmarks/held_out_calibration.py``
records the run, the chapter "Does the model check say no when it should?" shows it).

Each case is a 64 x 128 map (by default) of one of :data:`KINDS`:

- ``"stationary"``: eq 18 with one of :data:`~roughgp.experiments.check_calibration.CASES`
  (cycled), a tilted plane added: one model describes the whole map;
- ``"holes"``: the same with a rectangle and a disc unmeasured (about 9 %);
- ``"hierarchical"``: each half of the map its own region of a population: the variance times
  :math:`e^{0.4 g}` and each length times :math:`e^{0.25 g'}` (:math:`g, g'` standard normal,
  drawn per half): a model of one half does *not* describe the other;
- ``"gradient"``: the stationary map times a smooth amplitude that triples the variance from
  the left edge to the right (a modulated, non-stationary process).

eq 18 is fitted to the left half (the block likelihood as in
:mod:`roughgp.experiments.model_check`: 16-point blocks, 10 of them) and checked
(:func:`roughgp.checking.model_check.check_model`, 19 simulations) in these ways
(:data:`VARIANTS`): on the left half it saw (``in-sample``), on the right half with the plug-in
simulations (``held-out``), with the true model of the right half (``held-out-true``: the
check's own level, 2 / 20 = 10 % for every kind), and with the predictive simulations of
:mod:`roughgp.checking.predictive` (``predictive``: ``n_models`` bootstrap refits,
bias-corrected; ``predictive-fit``: centred on the fit), and, for a Whittle fit, with each
simulation's parameters drawn from the fit's sandwich covariance
(:mod:`roughgp.checking.sandwich_draws`, ``predictive-sandwich``: no refits). The tile check
(:mod:`roughgp.checking.tiles`, 2 x 4 tiles of the whole map, plug-in) gives the shares of
outside tiles on the left (fitted) and the right (held-out) half.

For ``stationary`` and ``holes`` (:data:`DESCRIBED`) the model's family describes the surface:
a check that is calibrated says "outside" in about 10 % of the cases per parameter out of
sample (:func:`calibration_shares`, with intervals; recorded at 64 x 128 and 256 x 512,
:func:`recorded_path`). For ``hierarchical`` and ``gradient`` it does not, and the held-out
check should say so more often.
"""

from __future__ import annotations

import dataclasses
import time
from pathlib import Path

import numpy as np

from roughgp.checking.held_out import part_of
from roughgp.checking.model_check import SURFACE_PARAMETERS, check_model
from roughgp.checking.predictive import bootstrap_models, recentred
from roughgp.checking.ranks import verdict_within
from roughgp.checking.sandwich_draws import sandwich_models
from roughgp.checking.tiles import TILE_PARAMETERS, tile_check
from roughgp.common.jsonl import read_records
from roughgp.experiments.check_calibration import CASES
from roughgp.experiments.model_check import synthetic_holes
from roughgp.surface_models.fit import fit_surface_model
from roughgp.surface_models.model import FittedModel

__all__ = ["KINDS", "VARIANTS", "SHAPE", "TILES", "VARIANCE_SPREAD", "LENGTH_SPREAD",
           "eq18_model", "synthetic_map", "held_out_case",
           "outside_shares", "shares_table", "DESCRIBED", "recorded_path", "calibration_shares",
           "calibration_table", "calibration_summary", "cases_to_decide", "summary_markdown",
           "plot_calibration"]

KINDS = ("stationary", "holes", "hierarchical", "gradient")
#: the kinds whose every half one eq 18 model describes (the check's level is judged on them)
DESCRIBED = ("stationary", "holes")
#: the checks of each case (module docstring); the predictive ones only with n_models > 0
VARIANTS = ("in-sample", "held-out", "held-out-true", "predictive", "predictive-fit",
            "predictive-sandwich")
SHAPE = (64, 128)
TILES = (2, 4)
_BLOCK, _N_BLOCKS = 16, 10
VARIANCE_SPREAD, LENGTH_SPREAD = 0.4, 0.25  # the hierarchical population's log spreads
_GRADIENT = 3.0  # the gradient kind's variance ratio, right edge to left
#: the recorded run (``benchmarks/held_out_calibration.py``: one :func:`held_out_case` a line)
RECORDED = Path(__file__).resolve().parents[2] / "benchmarks" / "results" / \
    "held_out_calibration.jsonl"


def eq18_model(variance, lam_a, lam_b, angle, noise) -> FittedModel:
    """Eq 18 of these hyperparameters (um, um^2, deg) on a 1 um grid, a plane its form."""
    return FittedModel("eq18", {"variance_um2": variance, "lambda_a_um": lam_a,
                                "lambda_b_um": lam_b, "angle_deg": angle,
                                "noise_variance_um2": noise}, (1.0, 1.0),
                       cutoffs={"form": "plane", "s_um": None, "l_um": None})


def synthetic_map(kind, index, *, shape=SHAPE, seed=0):
    """``(z, truth_left, truth_right)``: the ``index``-th synthetic map of ``kind`` (module
    docstring) and the true models of its halves (for ``gradient`` the model at the halves'
    mean amplitude)."""
    if kind not in KINDS:
        raise ValueError(f"kind must be one of {', '.join(KINDS)}, got {kind!r}")
    rng = np.random.default_rng([seed, KINDS.index(kind), index])
    variance, lam_a, lam_b, angle, noise = CASES[index % len(CASES)]
    ny, nx = shape
    half = nx // 2
    truth = eq18_model(variance, lam_a, lam_b, angle, noise)
    left = right = truth
    if kind == "hierarchical":
        halves = []
        for _ in range(2):
            g = rng.standard_normal(3)
            halves.append(eq18_model(variance * np.exp(VARIANCE_SPREAD * g[0]),
                                     lam_a * np.exp(LENGTH_SPREAD * g[1]),
                                     lam_b * np.exp(LENGTH_SPREAD * g[2]), angle, noise))
        left, right = halves
        z = np.concatenate([left.simulate(shape, seed=rng)[:, :half],
                            right.simulate(shape, seed=rng)[:, half:]], axis=1)
    else:
        z = truth.simulate(shape, seed=rng)
    if kind == "gradient":
        x = np.arange(nx) / (nx - 1) - 0.5
        z = z * np.exp(0.5 * np.log(_GRADIENT) * x)[None, :]
        scale = [float(np.mean(np.exp(np.log(_GRADIENT) * x[s])))
                 for s in (slice(0, half), slice(half, nx))]
        left, right = (dataclasses.replace(truth, hyperparameters={
            **truth.hyperparameters, "variance_um2": variance * s,
            "noise_variance_um2": noise * s}) for s in scale)
    iy, ix = np.indices(shape)
    z = z + 0.01 * ix - 0.02 * iy
    if kind == "holes":
        z = np.where(synthetic_holes(shape, rng), np.nan, z)
    return z, left, right


def held_out_case(kind, index, *, shape=SHAPE, n_simulations=19, n_models=9, seed=0,
                  likelihood="blocks", sandwich=False) -> dict:
    """One case (module docstring): the fitted hyperparameters, the parameters outside per
    variant, the tile check's outside shares per half, and the seconds taken. ``likelihood``:
    the fit's (:data:`~roughgp.surface_models.fit.LIKELIHOODS`; ``"whittle"`` uses every point
    of the half instead of the blocks). ``sandwich`` (Whittle fits only): add the variant
    ``predictive-sandwich``, each simulation's parameters drawn from the fit's large-sample
    distribution (:func:`~roughgp.checking.sandwich_draws.sandwich_models`; no refits); its
    ``sandwich_refused`` says why where they cannot be drawn."""
    if sandwich and likelihood != "whittle":
        raise ValueError("sandwich=True needs likelihood='whittle' (the draws use the Whittle "
                         f"fit's sandwich covariance), got likelihood={likelihood!r}")
    began = time.perf_counter()
    z, _, truth_right = synthetic_map(kind, index, shape=shape, seed=seed)
    fitted_part, held_part = part_of(z.shape, "left"), part_of(z.shape, "right")
    result = fit_surface_model(fitted_part.cut(z), 1.0, block=_BLOCK, n_blocks=_N_BLOCKS,
                               seed=seed + index, likelihood=likelihood)
    fitted = result.model
    a, b = fitted_part.cut(z), held_part.cut(z)
    check_seed = int(np.random.default_rng([seed, index, 7]).integers(2**31))
    options = dict(n_simulations=n_simulations, seed=check_seed)
    outside = {"in-sample": check_model(fitted, a, **options).outside,
               "held-out": check_model(fitted, b, **options).outside,
               "held-out-true": check_model(truth_right, b, **options).outside}
    if n_models:
        refits = bootstrap_models(fitted, n_models, shape=a.shape, seed=seed + index,
                                  centre="refits")
        for variant, centre in (("predictive", "bias-corrected"), ("predictive-fit", "fit")):
            outside[variant] = check_model(fitted, b, models=recentred(fitted, refits, centre),
                                           **options).outside
    refused = None
    if sandwich:
        try:
            drawn = sandwich_models(fitted, result.block_fit, np.isfinite(result.texture.sl),
                                    n_simulations, seed=check_seed)
            outside["predictive-sandwich"] = check_model(fitted, b, models=drawn.models,
                                                         **options).outside
        except ValueError as error:
            refused = str(error)
    tiles = tile_check(fitted, z, tiles=TILES, **options)
    n_cols = TILES[1] // 2
    tile_shares = {name: {"left": float(tiles.outside[:, :n_cols, k].mean()),
                          "right": float(tiles.outside[:, n_cols:, k].mean())}
                   for k, name in enumerate(tiles.names)}
    return {"kind": kind, "index": int(index), "seed": int(seed), "shape": list(shape),
            "likelihood": likelihood,
            "n_simulations": int(n_simulations), "n_models": int(n_models),
            "fitted": {k: float(v) for k, v in fitted.hyperparameters.items()},
            "truth_right": {k: float(v) for k, v in truth_right.hyperparameters.items()},
            "outside": outside, "tiles": tile_shares,
            **({"sandwich_refused": refused} if refused else {}),
            "seconds": round(time.perf_counter() - began, 2)}


def _fitted_by(record) -> str:
    return record.get("likelihood", "blocks")


def outside_shares(records, kind, variant, names=SURFACE_PARAMETERS,
                   likelihood="blocks") -> dict | None:
    """``{parameter: share of the cases outside}`` of ``kind``'s records fitted with
    ``likelihood`` under ``variant`` (None when no record has it), with ``"cases"`` their
    number and ``"mean"`` the share averaged over ``names``."""
    rows = [r for r in records if r["kind"] == kind and variant in r["outside"]
            and _fitted_by(r) == likelihood]
    if not rows:
        return None
    shares = {n: float(np.mean([n in r["outside"][variant] for r in rows])) for n in names}
    return {**shares, "mean": float(np.mean(list(shares.values()))), "cases": len(rows)}


def tile_shares(records, kind, side, names=TILE_PARAMETERS, likelihood="blocks") -> dict | None:
    """The tile check's mean outside share per parameter of ``kind``'s records fitted with
    ``likelihood`` on ``side`` (``"left"``, fitted, or ``"right"``, held out)."""
    rows = [r for r in records if r["kind"] == kind and _fitted_by(r) == likelihood]
    if not rows:
        return None
    return {n: float(np.mean([r["tiles"][n][side] for r in rows])) for n in names}


def shares_table(records, names=("Sq", "Sa", "Sk", "Sal", "Str", "Std"),
                 likelihood="blocks") -> str:
    """A Markdown table of the records fitted with ``likelihood``: per kind and variant, the
    cases, the share outside averaged over the 13 parameters and for ``names``; then the tile
    check's shares."""
    head = ["kind", "check", "cases", "mean of 13", *names]
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    for kind in KINDS:
        for variant in VARIANTS:
            s = outside_shares(records, kind, variant, likelihood=likelihood)
            if s is None:
                continue
            lines.append(f"| {kind} | {variant} | {s['cases']} | {s['mean']:.0%} | "
                         + " | ".join(f"{s[n]:.0%}" for n in names) + " |")
    lines += ["", "| kind | tiles | " + " | ".join(TILE_PARAMETERS) + " |",
              "|---|---|" + "---|" * len(TILE_PARAMETERS)]
    for kind in KINDS:
        for side, label in (("left", "fitted half"), ("right", "held-out half")):
            s = tile_shares(records, kind, side, likelihood=likelihood)
            if s is not None:
                lines.append(f"| {kind} | {label} | "
                             + " | ".join(f"{s[n]:.0%}" for n in TILE_PARAMETERS) + " |")
    return "\n".join(lines)


def recorded_path(shape=SHAPE) -> Path:
    """The recorded run of maps of ``shape``: :data:`RECORDED` for the default shape, else
    ``held_out_calibration_<ny>x<nx>.jsonl`` beside it."""
    shape = tuple(int(n) for n in shape)
    return RECORDED if shape == SHAPE else RECORDED.with_name(
        f"{RECORDED.stem}_{shape[0]}x{shape[1]}.jsonl")


def _wilson(k, n) -> tuple[float, float]:
    """The 95 % Wilson interval of ``k`` cases of ``n`` (``scipy.stats.binomtest``), as floats."""
    from scipy.stats import binomtest
    interval = binomtest(int(k), int(n)).proportion_ci(0.95, method="wilson")
    return float(interval.low), float(interval.high)


def calibration_shares(records, *, kinds=DESCRIBED, variants=VARIANTS,
                       names=SURFACE_PARAMETERS, likelihood="blocks") -> dict:
    """``{variant: {parameter: (share, low, high, verdict)}}`` over ``kinds``' cases (those the
    model's family describes) fitted with ``likelihood``, plus ``"cases"`` per variant: the
    share outside with its 95 % Wilson interval (``scipy.stats.binomtest``: unlike a normal
    interval, not empty at 0 of n) and the verdict on 10 % +- 3 %
    (:func:`~roughgp.checking.ranks.verdict_within`: yes, no or undecided). Variants with
    fewer than 2 cases are left out."""
    out = {}
    for variant in variants:
        rows = [r for r in records if r["kind"] in kinds and variant in r["outside"]
                and _fitted_by(r) == likelihood]
        if len(rows) < 2:
            continue
        shares = {"cases": len(rows)}
        for name in names:
            k = sum(name in r["outside"][variant] for r in rows)
            low, high = _wilson(k, len(rows))
            shares[name] = (k / len(rows), low, high, verdict_within(low, high))
        out[variant] = shares
    return out


def calibration_table(records, *, kinds=DESCRIBED, variants=VARIANTS,
                      names=SURFACE_PARAMETERS, likelihood="blocks") -> str:
    """A Markdown table of :func:`calibration_shares`: per variant (rows) and parameter
    (columns), the share outside, its 95 % interval and the verdict (yes, no or ?)."""
    head = ["check", "cases", *names]
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    mark = {"yes": "yes", "no": "no", "undecided": "?"}
    for variant, shares in calibration_shares(records, kinds=kinds, variants=variants,
                                              names=names, likelihood=likelihood).items():
        cells = [f"{shares[n][0]:.0%} [{shares[n][1]:.0%}, {shares[n][2]:.0%}] "
                 f"{mark[shares[n][3]]}" for n in names]
        lines.append(f"| {variant} | {shares['cases']} | " + " | ".join(cells) + " |")
    return "\n".join(lines)


def calibration_summary(records, *, kinds=DESCRIBED, variants=VARIANTS,
                        names=SURFACE_PARAMETERS, likelihood="blocks") -> list[dict]:
    """Per variant of :func:`calibration_shares`: its cases, the share outside averaged over
    ``names``, and how many parameters are within 10 % +- 3 % (``yes``), beyond it (``no``)
    or undecided, and which are beyond (``beyond``)."""
    rows = []
    for variant, shares in calibration_shares(records, kinds=kinds, variants=variants,
                                              names=names, likelihood=likelihood).items():
        verdicts = [shares[n][3] for n in names]
        rows.append({"check": variant, "cases": shares["cases"],
                     "mean": float(np.mean([shares[n][0] for n in names])),
                     "yes": verdicts.count("yes"), "undecided": verdicts.count("undecided"),
                     "no": verdicts.count("no"),
                     "beyond": [n for n in names if shares[n][3] == "no"]})
    return rows


def cases_to_decide(target=0.1, tolerance=0.03, *, step=10) -> int:
    """The fewest cases (a multiple of ``step``) at which a share of exactly ``target`` gets a
    95 % Wilson interval within ``target`` +- ``tolerance``: fewer cannot show a calibrated
    check "within" (:func:`calibration_shares`), only "beyond"."""
    n = step
    while True:
        k = round(target * n)
        if k / n == target and verdict_within(*_wilson(k, n), target, tolerance) == "yes":
            return n
        n += step


def summary_markdown(summary) -> str:
    """A Markdown table of :func:`calibration_summary`'s rows (one line per check)."""
    lines = ["| check | cases | mean of 13 | within 10 % ± 3 % | undecided | beyond | beyond it |",
             "|---|---|---|---|---|---|---|"]
    for row in summary:
        lines.append(f"| {row['check']} | {row['cases']} | {row['mean']:.1%} | {row['yes']} | "
                     f"{row['undecided']} | {row['no']} | {', '.join(row['beyond']) or '-'} |")
    return "\n".join(lines)


def plot_calibration(records, *, kinds=DESCRIBED, variants=VARIANTS, names=SURFACE_PARAMETERS,
                     likelihood="blocks"):
    """Per parameter, each variant's share of ``kinds``' cases outside with its 95 % interval
    (:func:`calibration_shares`), over the band 10 % +- 3 %. Returns the figure."""
    import matplotlib.pyplot as plt
    shares = calibration_shares(records, kinds=kinds, variants=variants, names=names,
                                likelihood=likelihood)
    fig, ax = plt.subplots(figsize=(6.8, 3.6), constrained_layout=True)
    ax.axhspan(7, 13, color="0.9", label="10 % ± 3 %")
    x = np.arange(len(names))
    width = 0.8 / max(len(shares), 1)
    for v, (variant, s) in enumerate(shares.items()):
        at = x + (v - (len(shares) - 1) / 2) * width
        mid = np.array([100 * s[n][0] for n in names])
        err = np.array([[100 * (s[n][0] - s[n][1]) for n in names],
                        [100 * (s[n][2] - s[n][0]) for n in names]])
        ax.errorbar(at, mid, yerr=err, fmt="o", ms=3, lw=0.8, capsize=1.5,
                    label=f"{variant} ({s['cases']})")
    ax.set_xticks(x, names, rotation=45)
    ax.set_ylabel("cases outside (%)")
    ax.legend(fontsize=9, ncol=3, loc="lower center", bbox_to_anchor=(0.5, 1.0),
              frameon=False)
    return fig


def load_records(path=RECORDED) -> list:
    """The cases recorded in the JSONL file ``path`` (one :func:`held_out_case` a line; none
    when the file does not exist)."""
    return read_records(path)


def plot_outside_shares(records, names=("mean", "Sq"), variants=VARIANTS, likelihood="blocks"):
    """One panel per entry of ``names`` (``"mean"``: the share averaged over the 13
    parameters): per kind, a bar per variant for the share of cases outside (the records
    fitted with ``likelihood``), and the check's level 2 / (n + 1). Returns the figure."""
    import matplotlib.pyplot as plt
    level = 2.0 / (records[0]["n_simulations"] + 1)
    variants = [v for v in variants if any(outside_shares(records, kind, v,
                                                          likelihood=likelihood)
                                           for kind in KINDS)]
    fig, axes = plt.subplots(1, len(names), figsize=(7.6, 3.0), sharey=True,
                             constrained_layout=True)
    axes = np.atleast_1d(axes)
    width = 0.8 / len(variants)
    x = np.arange(len(KINDS))
    for ax, name in zip(axes, names):
        for v, variant in enumerate(variants):
            shares = [outside_shares(records, kind, variant, likelihood=likelihood)
                      for kind in KINDS]
            ax.bar(x + (v - (len(variants) - 1) / 2) * width,
                   [100 * s[name] if s else np.nan for s in shares], width, label=variant)
        ax.axhline(100 * level, color="k", ls="--", lw=0.8)
        ax.set_xticks(x, KINDS)
        ax.set_title("mean of the 13 parameters" if name == "mean" else name)
    axes[0].set_ylabel("cases outside (%)")
    axes[-1].legend(loc="upper left")
    return fig
