r"""How often does the model check say "outside"? A lower-variance estimate from the ranks among
many simulations, and a test that the ranks are uniform (beyond the paper).

:func:`roughgp.checking.model_check.check_model` calls a parameter "outside" when the measured
value :math:`x` lies strictly below or strictly above all :math:`n` simulated values (two-sided
rank test; :math:`n = 19` gives 2/20 = 10 % for a measurement of the checked model). To measure
how often that happens over many synthetic measurements, each verdict is a 0/1 draw, and a
share over :math:`N` cases scatters by :math:`\sqrt{p(1-p)/N}` (4.2 % for :math:`p = 0.1`,
:math:`N = 50`).

**Rao-Blackwellised share.** Draw :math:`M \gg n` simulations instead, :math:`a` of them
strictly above :math:`x`, :math:`b` strictly below. The check's :math:`n` simulations are then
as good as :math:`n` of the :math:`M` drawn without replacement, and its verdict's conditional
expectation given the :math:`M` is hypergeometric,

.. math::

    \pi(a, b) = \frac{\binom{a}{n} + \binom{b}{n}}{\binom{M}{n}},

the probability that all :math:`n` lie above or all below (:func:`outside_probability`; ties
with :math:`x` count as neither, as in the check). :math:`\binom{a}{n} / \binom{M}{n}` is the
U-statistic of :math:`(1 - F(x))^n`, so :math:`\pi` has the 0/1 verdict's expectation
:math:`(1 - F(x))^n + F(x)^n` given :math:`x`, and averaged over cases the same mean as the 0/1
share, with a smaller scatter: for a calibrated check the rank :math:`b` is uniform on
:math:`0 .. M` and :math:`\pi(M - b, b)` has mean exactly :math:`2 / (n + 1)` and a standard
deviation of 0.20 for :math:`n = 19` (:func:`uniform_rank_sd`), against the 0/1 verdict's
0.30; the share's scatter over :math:`N` cases is that divided by :math:`\sqrt N`.

**Uniformity of the ranks (PIT).** Under the checked model the mid-rank
:math:`u = (b + (t + 1) / 2) / (M + 1)` (:math:`t` ties) is uniform on (0, 1) up to a step of
:math:`1 / (M + 1)`; :func:`pit_pvalue` gives the Kolmogorov-Smirnov p-value of the cases'
:math:`u` against the uniform law. It tells more than the share: a model that pins a parameter
puts the measurement in the middle of its simulations (``u`` piled up near 0.5), one that is
too narrow puts it at the ends.

Simulated values that are not finite are left out, as the check leaves them out: :math:`M` is
then the count of the finite ones (an approximation when the check's own :math:`n` contained a
NaN; :func:`rank_counts` returns the count so that it can be reported).
"""

from __future__ import annotations

import numpy as np
from scipy import special, stats

__all__ = ["rank_counts", "outside_probability", "uniform_rank_sd", "pit_values", "pit_pvalue",
           "share_interval", "verdict_within", "chance_within", "pass_chance"]


def rank_counts(measured, simulated):
    """``(above, below, ties, finite)``: the finite simulated values strictly above, strictly
    below and equal to ``measured``, and how many are finite. ``simulated`` is 1-D; a measured
    value that is not finite gives zero counts above and below (the check never calls it
    outside)."""
    sims = np.asarray(simulated, dtype=np.float64)
    if sims.ndim != 1:
        raise ValueError(f"simulated must be 1-D, got shape {sims.shape}")
    finite = sims[np.isfinite(sims)]
    if not np.isfinite(measured):
        return 0, 0, 0, int(finite.size)
    above, below = int(np.sum(finite > measured)), int(np.sum(finite < measured))
    return above, below, int(finite.size) - above - below, int(finite.size)


def _log_comb(m, k):
    m = np.asarray(m, dtype=np.float64)
    return special.gammaln(m + 1) - special.gammaln(k + 1) - special.gammaln(m - k + 1)


def outside_probability(above, below, finite, n_simulations=19):
    r"""The module docstring's :math:`\pi`: the probability that ``n_simulations`` values drawn
    without replacement from ``finite`` ones, ``above`` of them above the measurement and
    ``below`` below, all lie above or all below it. Arrays broadcast.

    Raises:
        ValueError: when ``n_simulations`` is not an integer >= 1, or a count is negative or
            ``above + below > finite``, or ``finite < n_simulations``.
    """
    if not isinstance(n_simulations, (int, np.integer)) or n_simulations < 1:
        raise ValueError(f"n_simulations must be an integer >= 1, got {n_simulations!r}")
    above, below, finite = (np.asarray(v, dtype=np.int64) for v in (above, below, finite))
    if (above < 0).any() or (below < 0).any() or (above + below > finite).any():
        raise ValueError("above and below must be >= 0 with above + below <= finite")
    if (finite < n_simulations).any():
        raise ValueError(f"finite (the simulations drawn) must be >= n_simulations = "
                         f"{n_simulations}, got {int(finite.min())}")
    n = int(n_simulations)
    total = _log_comb(finite, n)

    def part(count):
        with np.errstate(invalid="ignore"):
            return np.where(count >= n, np.exp(_log_comb(np.maximum(count, n), n) - total), 0.0)

    return part(above) + part(below)


def uniform_rank_sd(n_draws, n_simulations=19):
    r"""The standard deviation of :math:`\pi` for a calibrated check: the rank ``b`` uniform on
    ``0 .. n_draws`` (``a = n_draws - b``). Its mean is ``2 / (n_simulations + 1)`` exactly;
    for ``n_draws`` to infinity the sd tends to 0.203 (``n_simulations`` = 19)."""
    below = np.arange(n_draws + 1)
    values = outside_probability(n_draws - below, below, n_draws, n_simulations)
    return float(values.std())


def pit_values(below, ties, finite):
    """The mid-ranks ``(below + (ties + 1) / 2) / (finite + 1)`` in (0, 1)."""
    below, ties, finite = (np.asarray(v, dtype=np.float64) for v in (below, ties, finite))
    return (below + (ties + 1) / 2) / (finite + 1)


def pit_pvalue(below, ties, finite) -> float:
    """Kolmogorov-Smirnov p-value of the cases' mid-ranks (:func:`pit_values`) against the
    uniform law on (0, 1): small when the measurement's rank among the simulations is not
    uniform, i.e. when the checked model does not describe how the measurement came about."""
    u = pit_values(below, ties, finite)
    if u.size < 2:
        raise ValueError(f"a uniformity test needs at least 2 cases, got {u.size}")
    return float(stats.kstest(u, "uniform").pvalue)


def share_interval(values, z=1.96):
    """``(mean, low, high)``: the mean of the per-case ``values`` (0/1 verdicts or
    :math:`\\pi`) with a normal interval of ``z`` standard errors (the cases are independent
    draws; the empirical standard deviation, ddof 1), clipped to [0, 1]."""
    values = np.asarray(values, dtype=np.float64)
    if values.size < 2:
        raise ValueError(f"an interval needs at least 2 cases, got {values.size}")
    mean = float(values.mean())
    half = float(z * values.std(ddof=1) / np.sqrt(values.size))
    return mean, max(mean - half, 0.0), min(mean + half, 1.0)


def verdict_within(low, high, target=0.1, tolerance=0.03) -> str:
    """Is the share within ``target`` +- ``tolerance``, given its interval ``[low, high]``?
    ``"yes"`` when the whole interval lies within, ``"no"`` when it lies wholly outside,
    ``"undecided"`` otherwise (the cases are too few to tell)."""
    lo, hi = target - tolerance, target + tolerance
    if lo <= low and high <= hi:
        return "yes"
    if high < lo or low > hi:
        return "no"
    return "undecided"


def chance_within(n_cases, *, n_parameters=13, n_draws=99, n_simulations=19, tolerance=0.03,
                  n_trials=4000, seed=0):
    """How often a *perfectly calibrated* check meets "10 % +- ``tolerance`` per parameter" over
    ``n_cases`` cases, judged by the Rao-Blackwellised share's point estimate: ``(one, all)``,
    the chance for one parameter and for all ``n_parameters`` at once, were they independent.
    Monte Carlo over ``n_trials`` calibrations: each case's rank uniform on ``0 .. n_draws``,
    its :func:`outside_probability` averaged over the cases. It says how many cases a target
    of this kind needs before a miss means something (50 cases: 0.67 and 0.005; 550: 0.999
    and 0.98, with the defaults).

    Raises:
        ValueError: when ``n_cases``, ``n_parameters`` or ``n_trials`` is not an integer >= 1,
            or ``tolerance`` is not in (0, 1).
    """
    for name, value in (("n_cases", n_cases), ("n_parameters", n_parameters),
                        ("n_trials", n_trials)):
        if not isinstance(value, (int, np.integer)) or value < 1:
            raise ValueError(f"{name} must be an integer >= 1, got {value!r}")
    if not 0 < tolerance < 1:
        raise ValueError(f"tolerance must be in (0, 1), got {tolerance!r}")
    rng = np.random.default_rng(seed)
    target = 2.0 / (n_simulations + 1)
    within = np.empty((n_trials, n_parameters), dtype=bool)
    for t in range(n_trials):      # one calibration at a time: memory n_parameters x n_cases
        below = rng.integers(0, n_draws + 1, size=(n_parameters, n_cases))
        share = outside_probability(n_draws - below, below, n_draws, n_simulations).mean(axis=1)
        within[t] = np.abs(share - target) <= tolerance
    return float(within.mean()), float(within.all(axis=1).mean())


def pass_chance(n_parameters=13, most=2, chance=None, n_simulations=19) -> float:
    """The chance that a check leaves at most ``most`` of ``n_parameters`` outside when each is
    outside with probability ``chance`` (default the level of ``n_simulations`` draws,
    2 / (n + 1)), the parameters independent: the binomial yardstick for "the model reproduces
    the map" (at most 2 of 13 outside). Correlated parameters (Sq, Sa, Sk) pass somewhat more
    often, a check above its level less."""
    import scipy.stats
    p = 2.0 / (n_simulations + 1) if chance is None else float(chance)
    if not 0.0 <= p <= 1.0:
        raise ValueError(f"chance must be in [0, 1], got {chance!r}")
    return float(scipy.stats.binom.cdf(int(most), int(n_parameters), p))
