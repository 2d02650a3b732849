r"""The records of the model check's calibration and what they tell (beyond the paper):
per synthetic measurement the ranks of its texture parameters among the simulations of the
true and of the fitted model (:class:`CheckRanks`), and over the cases (:class:`Calibration`)
the plain and the Rao-Blackwellised share outside, their intervals, the ranks' uniformity and
the verdict on 10 % +- 3 % per parameter (:mod:`roughgp.checking.ranks`).
:mod:`roughgp.experiments.model_check` runs the calibration and says what it measured.
"""

from __future__ import annotations

import dataclasses
import json
from pathlib import Path

import numpy as np

from roughgp.checking.ranks import (outside_probability, pit_pvalue, pit_values,
                                                 share_interval, uniform_rank_sd,
                                                 verdict_within)
from roughgp.surface_models.model import FittedModel

__all__ = ["CASES", "MIN_CASES_FOR_VERDICT", "TABLE_FORMAT", "CheckRanks", "CalibrationCase",
           "Calibration", "RECORDED", "load_calibration", "plot_intervals", "plot_shares"]

#: the cases below which no verdict on 10 % +- 3 % is given: the per-case RB values are
#: skewed (most near 0, a few near 1), and over a few cases their standard deviation, and so
#: the normal interval, comes out far too small (4 cases gave "no" for a calibrated parameter)
MIN_CASES_FOR_VERDICT = 50
#: how :meth:`Calibration.styled_table` prints its columns
TABLE_FORMAT = {"0/1 (%)": "{:.1f}", "RB (%)": "{:.1f}", "PIT p": "{:.2g}"}
#: (variance um^2, lambda_a um, lambda_b um, angle deg, noise variance um^2) of the known models;
#: lengths on a grid of spacing 1 um
CASES = ((1.0, 8.0, 3.0, 30.0, 0.01), (2.0, 5.0, 5.0, 0.0, 0.05), (0.5, 12.0, 2.5, -60.0, 0.02),
         (1.0, 4.0, 1.5, 90.0, 0.1), (1.5, 6.0, 3.0, 45.0, 0.0))


@dataclasses.dataclass(frozen=True)
class CheckRanks:
    """One synthetic measurement checked against one model with ``n_draws`` simulations: per
    parameter (in the calibration's ``names`` order) the measured value, the simulated values
    above, below and equal to it and the finite ones
    (:func:`~roughgp.checking.ranks.rank_counts`), and the parameters outside the
    plain check of the first ``n_simulations`` draws (what ``roughgp check`` with the same seed
    says)."""

    measured: tuple
    above: tuple
    below: tuple
    ties: tuple
    finite: tuple
    outside: tuple

    def to_dict(self) -> dict:
        return {f.name: list(getattr(self, f.name)) for f in dataclasses.fields(self)}


@dataclasses.dataclass(frozen=True)
class CalibrationCase:
    """One synthetic measurement: its index, the known model, its chain, the fitted model, and
    its :class:`CheckRanks` against the true and the fitted model."""

    index: int
    truth: FittedModel
    l_filter: float | None
    holes: bool
    fitted: FittedModel
    ranks_true: CheckRanks
    ranks_fitted: CheckRanks
    fit_seconds: float

    @property
    def outside_true(self) -> tuple:
        return self.ranks_true.outside

    @property
    def outside_fitted(self) -> tuple:
        return self.ranks_fitted.outside

    def to_dict(self) -> dict:
        """A JSON-ready record (the models as their hyperparameters)."""
        return {"index": self.index, "truth": dict(self.truth.hyperparameters),
                "l_filter": self.l_filter, "holes": self.holes,
                "fitted": dict(self.fitted.hyperparameters), "fit_seconds": self.fit_seconds,
                "ranks_true": self.ranks_true.to_dict(),
                "ranks_fitted": self.ranks_fitted.to_dict()}

    @classmethod
    def from_dict(cls, record) -> "CalibrationCase":
        def model(hyper):
            return FittedModel("eq18", dict(hyper), (1.0, 1.0),
                               cutoffs={"form": "plane", "s_um": None,
                                        "l_um": record["l_filter"]})
        ranks = {key: CheckRanks(**{k: tuple(v) for k, v in record[key].items()})
                 for key in ("ranks_true", "ranks_fitted")}
        return cls(int(record["index"]), model(record["truth"]), record["l_filter"],
                   bool(record["holes"]), model(record["fitted"]), ranks["ranks_true"],
                   ranks["ranks_fitted"], float(record["fit_seconds"]))


@dataclasses.dataclass(frozen=True)
class Calibration:
    """What :func:`calibrate` returns.

    Attributes:
        cases: the :class:`CalibrationCase` list.
        names: the parameters checked.
        n_simulations: of the check (19).
        n_draws: simulations drawn per check for the Rao-Blackwellised share (>= n_simulations).
        shape: of each synthetic measurement.
        seconds: wall time of the whole calibration.
    """

    cases: tuple
    names: tuple
    n_simulations: int
    n_draws: int
    shape: tuple
    seconds: float

    @property
    def expected(self) -> float:
        """2 / (n + 1): the share outside for a measurement of the checked model."""
        return 2.0 / (self.n_simulations + 1)

    def _ranks(self, which):
        if which not in ("true", "fitted"):
            raise ValueError(f"which must be 'true' or 'fitted', got {which!r}")
        return [c.ranks_true if which == "true" else c.ranks_fitted for c in self.cases]

    def verdicts(self, which="fitted") -> np.ndarray:
        """The plain check's 0/1 verdicts, cases x parameters."""
        return np.array([[name in r.outside for name in self.names]
                         for r in self._ranks(which)], dtype=np.float64)

    def outside_probabilities(self, which="fitted") -> np.ndarray:
        """The Rao-Blackwellised verdicts
        (:func:`~roughgp.checking.ranks.outside_probability` of the ranks among
        ``n_draws``), cases x parameters."""
        ranks = self._ranks(which)
        return np.array([outside_probability(r.above, r.below, r.finite, self.n_simulations)
                         for r in ranks])

    def fractions(self, which="fitted") -> dict:
        """``{parameter: share of the cases outside}``, the plain 0/1 count (``which``:
        "fitted" or "true")."""
        return dict(zip(self.names, self.verdicts(which).mean(axis=0).tolist()))

    def rb_fractions(self, which="fitted") -> dict:
        """``{parameter: Rao-Blackwellised share outside}``."""
        return dict(zip(self.names, self.outside_probabilities(which).mean(axis=0).tolist()))

    def mean_fraction(self, which="fitted", *, rao_blackwell=False) -> float:
        """The share outside averaged over the parameters."""
        shares = self.rb_fractions(which) if rao_blackwell else self.fractions(which)
        return float(np.mean(list(shares.values())))

    def binomial_sd(self) -> float:
        """The standard deviation of one parameter's 0/1 share over these cases, were each
        outside with probability :attr:`expected` independently."""
        p = self.expected
        return float(np.sqrt(p * (1 - p) / len(self.cases)))

    def rb_sd(self) -> float:
        """The standard deviation of one parameter's Rao-Blackwellised share over these cases
        for a calibrated check (a uniform rank among ``n_draws + 1``)."""
        return float(uniform_rank_sd(self.n_draws, self.n_simulations)
                     / np.sqrt(len(self.cases)))

    def _rank_counts(self, which, i):
        """``(below, ties, finite)`` of parameter ``i`` over the cases whose measured value is
        finite."""
        kept = [r for r in self._ranks(which) if np.isfinite(r.measured[i])]
        return tuple(np.array([getattr(r, key)[i] for r in kept], dtype=np.int64)
                     for key in ("below", "ties", "finite"))

    def pit_pvalues(self, which="fitted") -> dict:
        """``{parameter: Kolmogorov-Smirnov p-value of the ranks' uniformity}`` (cases with a
        measured value that is not finite left out)."""
        out = {}
        for i, name in enumerate(self.names):
            counts = self._rank_counts(which, i)
            out[name] = pit_pvalue(*counts) if counts[0].size > 1 else np.nan
        return out

    def summary(self, which="fitted", tolerance=0.03) -> list:
        """Per parameter a dict: the 0/1 share and its interval, the Rao-Blackwellised share
        and its interval (95 %, :func:`~roughgp.checking.ranks.share_interval`),
        the PIT p-value and whether the share is within :attr:`expected` +- ``tolerance``
        (:func:`~roughgp.checking.ranks.verdict_within` of the Rao-Blackwellised
        interval; "too few cases" under :data:`MIN_CASES_FOR_VERDICT`)."""
        plain, rb = self.verdicts(which), self.outside_probabilities(which)
        pit = self.pit_pvalues(which)
        rows = []
        for i, name in enumerate(self.names):
            share, low, high = share_interval(plain[:, i])
            rb_share, rb_low, rb_high = share_interval(rb[:, i])
            rows.append({"parameter": name, "share": share, "share_low": low,
                         "share_high": high, "rb": rb_share, "rb_low": rb_low,
                         "rb_high": rb_high, "pit_p": pit[name],
                         "within": verdict_within(rb_low, rb_high, self.expected, tolerance)
                         if len(self.cases) >= MIN_CASES_FOR_VERDICT else "too few cases"})
        return rows

    def shares_by_model(self, which="fitted") -> dict:
        """``{k: {parameter: Rao-Blackwellised share}}`` over the cases drawn from
        ``CASES[k]`` (the known model of case ``index`` is ``CASES[index % len(CASES)]``)."""
        values = self.outside_probabilities(which)
        model = np.array([c.index % len(CASES) for c in self.cases])
        return {int(k): dict(zip(self.names, values[model == k].mean(axis=0).tolist()))
                for k in np.unique(model)}

    def point_within(self, which="fitted", tolerance=0.03) -> list:
        """The parameters whose Rao-Blackwellised share (the point estimate, without its
        interval) lies within :attr:`expected` +- ``tolerance``."""
        return [name for name, share in self.rb_fractions(which).items()
                if abs(share - self.expected) <= tolerance]

    def by_verdict(self, which="fitted", tolerance=0.03) -> dict:
        """``{"yes": [...], "no": [...], "undecided": [...], "too few cases": [...]}``: the
        parameters by whether their Rao-Blackwellised share is within :attr:`expected` +-
        ``tolerance`` (:meth:`summary`)."""
        groups = {"yes": [], "no": [], "undecided": [], "too few cases": []}
        for row in self.summary(which, tolerance):
            groups[row["within"]].append(row["parameter"])
        return groups

    def matching_simulations(self, which="fitted") -> dict:
        """``{parameter: n}``: the number of simulations ``n`` (2 .. the fewest finite draws
        of a case, at most ``n_draws``) whose check would say "outside" in the share nearest
        to :attr:`expected` over these cases (the Rao-Blackwellised share for ``n``).
        :attr:`n_simulations` for a calibrated check; fewer where the check is conservative (the
        measurement too often in the middle), more where it cries wolf. A measure of how far off the
        check is, in its own unit; a correction only for measurements like these synthetic ones
        (another fit, another surface, another number)."""
        ranks = self._ranks(which)
        above = np.array([r.above for r in ranks])
        below = np.array([r.below for r in ranks])
        finite = np.array([r.finite for r in ranks])
        counts = np.arange(2, int(finite.min()) + 1)
        shares = np.array([outside_probability(above, below, finite, int(n)).mean(axis=0)
                           for n in counts])
        best = np.abs(shares - self.expected).argmin(axis=0)
        return {name: int(counts[best[i]]) for i, name in enumerate(self.names)}

    def mean_rank(self, which="fitted") -> dict:
        """``{parameter: mean mid-rank (PIT) over the cases}``: 0.5 for a calibrated check,
        above when the measurement tends to lie above the simulations (the model too small in
        that parameter), below when under them."""
        return {name: float(np.mean(pit_values(*self._rank_counts(which, i))))
                for i, name in enumerate(self.names)}

    def fit_ratios(self) -> dict:
        """``{quantity: (median, standard deviation)}`` over the cases of fitted / true for the
        variance, lambda_a, lambda_b, and the combination variance / sqrt(lambda_a lambda_b)
        (for the exponential ACVF of eq 18 the variance and the lengths are estimated
        together: a small map determines this combination better than either)."""
        def ratio(case, key):
            return case.fitted.hyperparameters[key] / case.truth.hyperparameters[key]
        values = {key: np.array([ratio(c, key) for c in self.cases])
                  for key in ("variance_um2", "lambda_a_um", "lambda_b_um")}
        values["variance / sqrt(lambda_a lambda_b)"] = values["variance_um2"] / np.sqrt(
            values["lambda_a_um"] * values["lambda_b_um"])
        return {key: (float(np.median(v)), float(np.std(v))) for key, v in values.items()}

    def middle_share(self, which="fitted") -> dict:
        """``{parameter: share of the cases whose rank lies in the middle half}`` (mid-rank
        between 0.25 and 0.75; 0.5 for a calibrated check, more when the model pins the
        parameter to the measurement, less when its simulations are too narrow)."""
        out = {}
        for i, name in enumerate(self.names):
            u = pit_values(*self._rank_counts(which, i))
            out[name] = float(np.mean((u > 0.25) & (u < 0.75)))
        return out

    def table(self, which=None):
        """A pandas DataFrame, a row per parameter, a column group per model ("true model",
        "fitted model"): the 0/1 share outside (%), the Rao-Blackwellised share (%) and its
        95 % interval, the PIT p-value and whether the share is within 10 % +- 3 %. With
        ``which`` ("true" or "fitted"), that model's columns alone (narrow enough for a page)."""
        import pandas as pd
        if which is not None:
            self._ranks(which)                  # refuses anything but "true" and "fitted"
            return self.table()[f"{which} model"]
        columns = {}
        for which in ("true", "fitted"):
            rows, group = self.summary(which), f"{which} model"
            columns[(group, "0/1 (%)")] = [100 * r["share"] for r in rows]
            columns[(group, "RB (%)")] = [100 * r["rb"] for r in rows]
            columns[(group, "RB 95 % (%)")] = [
                f"{100 * r['rb_low']:.1f} to {100 * r['rb_high']:.1f}" for r in rows]
            columns[(group, "PIT p")] = [r["pit_p"] for r in rows]
            columns[(group, "10 ± 3 %?")] = [r["within"] for r in rows]
        return pd.DataFrame(columns, index=pd.Index(self.names, name="parameter"))

    def styled_table(self, which):
        """:meth:`table` of one model (``which``: "true" or "fitted"), the shares to 0.1 % and
        the PIT p-value to two digits, captioned with the model and the number of cases."""
        return (self.table(which).style.format(TABLE_FORMAT)
                .set_caption(f"against the {which} model, {len(self.cases)} cases"))

    def first(self, n_cases) -> "Calibration":
        """The calibration of the ``n_cases`` cases of lowest index (e.g. the issue's 50 of a
        larger run; its ``seconds`` NaN)."""
        if not 1 <= n_cases <= len(self.cases):
            raise ValueError(f"n_cases must be in [1, {len(self.cases)}], got {n_cases}")
        cases = sorted(self.cases, key=lambda c: c.index)[:n_cases]
        return dataclasses.replace(self, cases=tuple(cases), seconds=float("nan"))

    def to_records(self) -> list:
        """One JSON-ready dict per case, with the calibration's settings in each."""
        head = {"names": list(self.names), "n_simulations": self.n_simulations,
                "n_draws": self.n_draws, "shape": list(self.shape)}
        return [{**head, **case.to_dict()} for case in self.cases]

    @classmethod
    def from_records(cls, records, seconds=float("nan")) -> "Calibration":
        """The calibration of ``records`` (:meth:`to_records`, e.g. read from a JSONL file);
        they must share their settings."""
        records = list(records)
        if not records:
            raise ValueError("no records")
        keys = ("names", "n_simulations", "n_draws", "shape")
        head = {k: records[0][k] for k in keys}
        for r in records:
            if {k: r[k] for k in keys} != head:
                raise ValueError(f"the records' settings differ: {head} against "
                                 f"{ {k: r[k] for k in keys} }")
        cases = sorted((CalibrationCase.from_dict(r) for r in records), key=lambda c: c.index)
        if len({c.index for c in cases}) != len(cases):
            raise ValueError("a case index occurs twice in the records")
        return cls(tuple(cases), tuple(head["names"]), int(head["n_simulations"]),
                   int(head["n_draws"]), tuple(head["shape"]), float(seconds))


#: the records of the large run (``benchmarks/model_check_calibration.py``, 64 x 64, seed 0)
RECORDED = Path(__file__).resolve().parents[2] / "benchmarks" / "results" / \
    "model_check_calibration_64.jsonl"


def load_calibration(path=RECORDED) -> Calibration:
    """The calibration recorded in the JSONL file ``path`` (one :meth:`Calibration.to_records`
    record a line; ``benchmarks/model_check_calibration.py`` writes it)."""
    lines = Path(path).read_text(encoding="utf-8").splitlines()
    return Calibration.from_records(json.loads(line) for line in lines if line.strip())


def plot_intervals(names, level, series, ax, title):
    """Per parameter of ``names`` the shares of ``series`` (``(label, rows, key)``: ``rows`` a
    summary whose ``key``, ``key_low``, ``key_high`` are a share and its interval) side by side,
    and the band ``level`` +- 3 %. Returns the figure."""
    import matplotlib.pyplot as plt
    if ax is None:
        _, ax = plt.subplots(figsize=(7.6, 3.2))
    x = np.arange(len(names))
    ax.axhspan(100 * (level - 0.03), 100 * (level + 0.03), color="0.88", label="10 % ± 3 %")
    ax.axhline(100 * level, color="k", lw=1)
    for shift, (label, rows, key) in zip((-0.15, 0.15), series):
        share = np.array([100 * r[key] for r in rows])
        low = share - np.array([100 * r[key + "_low"] for r in rows])
        high = np.array([100 * r[key + "_high"] for r in rows]) - share
        ax.errorbar(x + shift, share, yerr=[low, high], fmt="o", ms=4, capsize=2, label=label)
    ax.set_xticks(x, names)
    ax.set_ylabel("cases outside (%)")
    ax.set_title(title, fontsize=10)
    ax.legend(ncol=3)
    return ax.figure


def plot_shares(cal: Calibration, ax=None, *, title=None):
    """Per parameter the Rao-Blackwellised share outside (%) with its 95 % interval, against
    the true and the fitted model, and the band 10 % +- 3 %. Returns the figure."""
    return plot_intervals(cal.names, cal.expected,
                           [("true model", cal.summary("true"), "rb"),
                            ("fitted model", cal.summary("fitted"), "rb")], ax,
                           title or f"{len(cal.cases)} synthetic measurements, {cal.n_draws} "
                                    f"simulations per check")
