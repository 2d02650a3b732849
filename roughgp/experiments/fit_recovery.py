r"""Does eq 18's fit recover a known surface, and does its precision grow with the map? (issue
40, item 2; ``benchmarks/fit_recovery.py`` records the run.)

Maps of :data:`SIZES` points square are drawn from one eq 18 model (:data:`TRUTH`: the issue's
null control, lambda_a 20 um along a lay at 30 degrees, lambda_b 5 um, unit spacing) and fitted
the way ``roughgp fit ground`` fits them (:func:`roughgp.surface_models.fit.fit_surface_model`:
the plane removed, then eq 18 plus noise) with each of
:data:`~roughgp.surface_models.fit.LIKELIHOODS`: the block composite likelihood (12 random
blocks of 24 x 24 points, whatever the map's size) and the debiased spatial Whittle likelihood
of every point. :func:`recovery_table` reports, per size and likelihood, the median of the
fitted / true ratio of the variance and the two lengths (the bias), the spread of its log
(the standard deviation of :math:`\log(\hat\theta/\theta)`, about the relative error), the
angle's median absolute error and the median seconds.
"""

from __future__ import annotations

import math
import time
from pathlib import Path

import numpy as np

from roughgp.common.jsonl import read_records
from roughgp.surface_models.fit import LIKELIHOODS, fit_surface_model
from roughgp.surface_models.model import FittedModel

__all__ = ["SIZES", "TRUTH", "RATIOS", "RECORDED", "load_records", "truth_model",
           "recovery_case", "recovery_summary", "recovery_table", "plot_recovery"]

SIZES = (128, 256, 512)
TRUTH = {"variance_um2": 10.0, "lambda_a_um": 20.0, "lambda_b_um": 5.0, "angle_deg": 30.0,
         "noise_variance_um2": 0.05}
RATIOS = ("variance_um2", "lambda_a_um", "lambda_b_um")  #: the parameters reported as ratios
#: the recorded run (``benchmarks/fit_recovery.py``: one :func:`recovery_case` a line)
RECORDED = Path(__file__).resolve().parents[2] / "benchmarks" / "results" / "fit_recovery.jsonl"


def load_records(path=RECORDED) -> list:
    """The fits recorded in the JSONL file ``path`` (none when it does not exist)."""
    return read_records(path)


def truth_model() -> FittedModel:
    return FittedModel("eq18", dict(TRUTH), (1.0, 1.0),
                       cutoffs={"form": "plane", "s_um": None, "l_um": None})


def recovery_case(size, seed, likelihood) -> dict:
    """One map of ``size`` x ``size`` points (seeded), fitted with ``likelihood``: the fitted
    hyperparameters and the seconds of the fit."""
    if likelihood not in LIKELIHOODS:
        raise ValueError(f"likelihood must be one of {', '.join(LIKELIHOODS)}, got "
                         f"{likelihood!r}")
    z = truth_model().simulate((int(size), int(size)), seed=np.random.default_rng([seed, size]))
    began = time.perf_counter()
    model = fit_surface_model(z, 1.0, seed=int(seed), likelihood=likelihood).model
    return {"size": int(size), "seed": int(seed), "likelihood": likelihood,
            "fitted": {k: float(model.hyperparameters[k]) for k in TRUTH},
            "seconds": round(time.perf_counter() - began, 2)}


def _angle_error(fitted_deg):
    return abs((fitted_deg - TRUTH["angle_deg"] + 90.0) % 180.0 - 90.0)


def recovery_summary(records, size, likelihood) -> dict | None:
    """Per :data:`RATIOS`: ``(median ratio, sd of log ratio)``; ``"angle"``: the median
    absolute error (degrees); ``"seconds"``, ``"cases"``. None without records."""
    rows = [r for r in records if r["size"] == size and r["likelihood"] == likelihood]
    if not rows:
        return None
    out = {"cases": len(rows), "seconds": float(np.median([r["seconds"] for r in rows])),
           "angle": float(np.median([_angle_error(r["fitted"]["angle_deg"]) for r in rows]))}
    for name in RATIOS:
        logs = np.log([r["fitted"][name] / TRUTH[name] for r in rows])
        out[name] = (float(np.exp(np.median(logs))), float(np.std(logs, ddof=1))
                     if len(logs) > 1 else math.nan)
    return out


def recovery_table(records) -> str:
    """A Markdown table of :func:`recovery_summary` per size and likelihood."""
    head = ["size", "likelihood", "cases", "variance: median ratio, sd of log",
            "lambda_a", "lambda_b", "angle error (deg)", "seconds"]
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    for size in sorted({r["size"] for r in records}):
        for likelihood in LIKELIHOODS:
            s = recovery_summary(records, size, likelihood)
            if s is None:
                continue
            cells = [f"{s[n][0]:.3f}, {s[n][1]:.3f}" for n in RATIOS]
            lines.append(f"| {size}² | {likelihood} | {s['cases']} | " + " | ".join(cells)
                         + f" | {s['angle']:.2f} | {s['seconds']:.1f} |")
    return "\n".join(lines)


def plot_recovery(records):
    """Per parameter of :data:`RATIOS` a panel: per size, the fitted/true ratios of each
    likelihood as a box (log scale), and the truth's line. Returns the figure."""
    import matplotlib.pyplot as plt
    sizes = sorted({r["size"] for r in records})
    fig, axes = plt.subplots(1, len(RATIOS), figsize=(7.6, 3.0), sharey=True,
                             constrained_layout=True)
    labels = {"variance_um2": "variance", "lambda_a_um": "λ_a", "lambda_b_um": "λ_b"}
    for ax, name in zip(axes, RATIOS):
        for k, likelihood in enumerate(LIKELIHOODS):
            data = [[r["fitted"][name] / TRUTH[name] for r in records
                     if r["size"] == size and r["likelihood"] == likelihood] for size in sizes]
            boxes = ax.boxplot(data, positions=np.arange(len(sizes)) + (k - 0.5) * 0.35,
                               widths=0.3, patch_artist=True, showfliers=True,
                               flierprops={"markersize": 3})
            for patch in boxes["boxes"]:
                patch.set_facecolor(f"C{k}")
                patch.set_alpha(0.6)
            ax.plot([], [], "s", color=f"C{k}", alpha=0.6, label=likelihood)
        ax.axhline(1.0, color="k", lw=0.8, ls="--")
        ax.set_yscale("log")
        ax.set_xticks(np.arange(len(sizes)), [f"{s}²" for s in sizes])
        ax.set_title(f"{labels[name]}: fitted / true")
    from matplotlib.ticker import FixedLocator, NullFormatter, NullLocator, ScalarFormatter
    axes[0].yaxis.set_major_locator(FixedLocator([0.5, 0.7, 0.8, 0.9, 1.0, 1.1, 1.25, 1.5, 2.0]))
    axes[0].yaxis.set_major_formatter(ScalarFormatter())
    axes[0].yaxis.set_minor_locator(NullLocator())
    axes[0].yaxis.set_minor_formatter(NullFormatter())
    axes[0].set_ylabel("ratio")
    axes[0].legend(loc="upper right")
    return fig
