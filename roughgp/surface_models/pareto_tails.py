r"""Generalized Pareto tails for the IAAFT quantile table (beyond the paper; issue 40).

The IAAFT marginal (:mod:`roughgp.surface_models.iaaft`) keeps the measured heights' quantile
function, extremes included. Its tails are one sample's: on a correlated surface the lowest
thousandth of a 128 x 128 crop is one or two pits, so the table's tail is lumpy, ends at the
crop's own minimum, and a simulation's extremes (the draw's lowest normal score through the
table) land near the crop's own Sv and Sp. Another crop of the same surface has its own
deepest pit, and its Sv, Sz and Sp fall outside the simulations far more often than the
check's level (``benchmarks/iaaft_held_out.py``: Sv outside on the other half of 11 of the
15 Gaussian maps; with the tile bootstrap below, 4).

Here the table's tails beyond :data:`TAIL_SHARE` of the heights on either side are the
generalized Pareto distribution (GPD) of the exceedances over that quantile, the limit law of
exceedances over a high threshold (Pickands 1975; Balkema and de Haan 1974): with
:math:`y = h - u \ge 0` above the threshold :math:`u`,

.. math::
    F(y) = 1 - (1 - k y / \sigma)^{1/k}, \qquad
    y(F) = \frac{\sigma}{k}\,\bigl(1 - (1 - F)^k\bigr)

(Hosking's sign, :math:`k = -\xi`: :math:`k > 0` a bounded tail, :math:`k < 0` a heavy one,
:math:`k \to 0` the exponential), fitted by probability-weighted moments (Hosking and Wallis,
Technometrics 29, 339 (1987): with :math:`a_0` the exceedances' mean and :math:`a_1` their
mean weighted by :math:`1 - p_i`, :math:`p_i = (i - 0.35)/n`,
:math:`k = a_0 / (a_0 - 2 a_1) - 2` and :math:`\sigma = 2 a_0 a_1 / (a_0 - 2 a_1)`), which,
unlike maximum likelihood, needs no iteration and is stable for the few hundred correlated
exceedances of a crop. The table spans the normal scores of :data:`TABLE_TAIL` (about
:math:`\pm 5.2`) instead of the measured extremes' plotting positions: the tail is a model of
the outer 5 %, not the sample's last few points. On Gaussian heights the GPD of a 5 %
threshold is a bounded tail (:math:`k \approx 0.13`) that falls short of the normal's far
tail: on 200 000 normal heights the table is within 3 % of the normal quantile up to 3 sd and
5 to 10 % short at 4.5 sd (``tests/surface_models/test_pareto_tails.py``), beyond what a crop's
simulations reach.

The tails alone change little (in a run on 10 of those maps, not recorded: 25 % of the
parameters outside on the other half against 28 %): a crop's exceedances are too few to pin
the tail down. They
matter for the tile bootstrap (:mod:`roughgp.checking.tile_bootstrap`), whose resampled tables
could otherwise only shrink the measured extremes (a resample that leaves out the deepest pit
has a shallower minimum, none has a deeper one).
"""

from __future__ import annotations

import numpy as np
import scipy.special

__all__ = ["TAIL_SHARE", "TABLE_TAIL", "MIN_EXCEEDANCES", "pwm_fit", "pareto_quantile",
           "pareto_tails_table"]

TAIL_SHARE = 0.05    #: the share of the heights on each side modelled by the GPD
TABLE_TAIL = 1e-7    #: the tail probability of the table's first and last quantile
MIN_EXCEEDANCES = 20  #: the fewest heights beyond each threshold the fit needs


def pwm_fit(exceedances) -> tuple[float, float]:
    """``(sigma, k)``: the GPD of the ``exceedances`` (>= 0, not all equal) by
    probability-weighted moments (module docstring)."""
    y = np.sort(np.asarray(exceedances, dtype=np.float64))
    if y.size < 2 or not np.all(np.isfinite(y)) or y[0] < 0 or not y[-1] > 0:
        raise ValueError("exceedances must be finite, >= 0, and not all 0")
    p = (np.arange(1, y.size + 1) - 0.35) / y.size
    a0 = float(y.mean())
    a1 = float(np.mean((1.0 - p) * y))
    denominator = a0 - 2.0 * a1
    if not denominator > 0:
        raise ValueError("the exceedances do not determine a generalized Pareto tail")
    return 2.0 * a0 * a1 / denominator, a0 / denominator - 2.0


def pareto_quantile(sigma, k, probability):
    """The GPD's quantile :math:`y(F)` (module docstring) at ``probability`` in [0, 1)."""
    f = np.asarray(probability, dtype=np.float64)
    if abs(k) < 1e-9:
        return -sigma * np.log1p(-f)
    return sigma / k * (1.0 - (1.0 - f) ** k)


def pareto_tails_table(heights, n_quantiles, share=TAIL_SHARE) -> tuple[list, float, dict]:
    """``(quantiles, tail_probability, tails)``: the IAAFT quantile table of the finite
    ``heights`` (``n_quantiles`` quantiles at equal steps of the normal score, as
    :func:`roughgp.surface_models.iaaft.quantile_table`) spanning the probabilities
    :data:`TABLE_TAIL` to 1 - :data:`TABLE_TAIL`: the measured quantiles between the
    ``share`` and 1 - ``share`` quantiles, the GPD of the exceedances beyond each (module
    docstring). ``tails``: what was fitted, ``{"model", "share", "low", "high"}`` with each
    side's ``[threshold_um, sigma_um, k]``."""
    h = np.asarray(heights, dtype=np.float64)
    h = np.sort(h[np.isfinite(h)])
    if not 0.0 < share < 0.5:
        raise ValueError(f"share must be in (0, 0.5), got {share!r}")
    if h.size * share < MIN_EXCEEDANCES:
        raise ValueError(f"generalized Pareto tails beyond {share:g} of the heights need at "
                         f"least {int(np.ceil(MIN_EXCEEDANCES / share))} measured heights, "
                         f"got {h.size}")
    t0 = float(scipy.special.ndtri(TABLE_TAIL))
    p = scipy.special.ndtr(np.linspace(t0, -t0, int(n_quantiles)))
    lowest = 0.5 / h.size
    q = np.quantile(h, np.clip(p, lowest, 1.0 - lowest), method="hazen")
    tails = {"model": "generalized Pareto (probability-weighted moments)", "share": share}
    for side, name in ((1.0, "high"), (-1.0, "low")):
        x = side * h
        threshold = float(np.quantile(x, 1.0 - share, method="hazen"))
        try:
            sigma, k = pwm_fit(x[x > threshold] - threshold)
        except ValueError as error:
            raise ValueError(f"the {name} tail of the heights: {error}") from None
        beyond = (p if side > 0 else 1.0 - p) > 1.0 - share
        tail_p = ((p if side > 0 else 1.0 - p)[beyond] - (1.0 - share)) / share
        q[beyond] = side * (threshold + pareto_quantile(sigma, k, tail_p))
        tails[name] = [side * threshold, sigma, k]
    return np.maximum.accumulate(q).tolist(), TABLE_TAIL, tails
