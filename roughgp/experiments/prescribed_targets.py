"""The verdicts on surfaces simulated with prescribed Sq, Sal, Str and Std (beyond the paper:
its conclusion's future work [16]), written once for the chapter "Prescribed roughness" and the
ledger's ``prescribed`` row (as :func:`~roughgp.experiments.measured_surfaces.fill_verdicts`
is for the measured surfaces)."""

from __future__ import annotations

import math

import numpy as np

__all__ = ["K_SE", "STD_TOLERANCE_DEG", "STRONG_LAY_STR", "target_verdicts"]

K_SE = 4.0  #: a mean hits its target within this many standard errors (Sq: predicted sd)
STD_TOLERANCE_DEG = 2.0  #: Std's circular mean within this many degrees for a strong lay ...
STRONG_LAY_STR = 0.2  #: ... that is, Str at most this; otherwise within K_SE standard errors


def target_verdicts(goal, values, sq_prediction) -> dict:
    """The verdicts on the parameters achieved by surfaces drawn for ``goal``: statement ->
    bool.

    Args:
        goal: the :class:`~roughgp.targets.closed_form.RoughnessTargets`.
        values: ``{"Sq": array, "Sal": ..., "Str": ..., "Std": ...}``, one value per surface
            (:func:`~roughgp.targets.closed_form.achieved_parameters`).
        sq_prediction: ``(mean, sd)`` of Sq on the field
            (:func:`~roughgp.targets.closed_form.sq_prediction`).
    """
    from roughgp import targets
    summary = targets.summarize(values)
    n = len(values["Sq"])
    sq_mean, sq_sd = sq_prediction
    out = {f"every surface's Sq within {K_SE:g} predicted sd of the predicted mean":
           bool(np.all(np.abs(np.asarray(values["Sq"]) - sq_mean) <= K_SE * sq_sd))}
    for k in ("Sal", "Str"):
        mean, sd = summary[k]
        out[f"the mean {k} within {K_SE:g} standard errors of its target"] = \
            bool(abs(mean - getattr(goal, k)) <= K_SE * sd / math.sqrt(n))
    mean, sd = summary["Std"]
    strong = goal.Str <= STRONG_LAY_STR
    tolerance = STD_TOLERANCE_DEG if strong else K_SE * sd / math.sqrt(n)
    out["Std's circular mean on target (" + (f"within {STD_TOLERANCE_DEG:g} deg: a strong lay"
                                            if strong else f"within {K_SE:g} standard errors")
        + ")"] = bool(abs(targets.direction_difference(mean, goal.Std)) <= tolerance)
    return out
