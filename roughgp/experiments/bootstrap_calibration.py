r"""The records of the calibrated model check's calibration and what they tell (beyond the
paper): per synthetic measurement (:func:`roughgp.experiments.model_check.bootstrap_case`) the
plain and the calibrated verdicts (:mod:`roughgp.checking.calibrated`) against
the fitted model, and over the cases their shares outside with their intervals, the verdict on
10 % +- 3 % per parameter, and the bootstrap's yardstick (how often the refitted copies lie
outside their range, against the measurements).
"""

from __future__ import annotations

import dataclasses
import json
from pathlib import Path

import numpy as np

from roughgp.checking.ranks import share_interval, verdict_within
from roughgp.experiments.check_calibration import (MIN_CASES_FOR_VERDICT, RECORDED,
                                                   plot_intervals)

__all__ = ["BootstrapCalibration", "BOOTSTRAP_RECORDED", "load_bootstrap", "plot_bootstrap"]


@dataclasses.dataclass(frozen=True)
class BootstrapCalibration:
    """How often the calibrated check (:mod:`roughgp.checking.calibrated`) says
    "outside" against the fitted model, per parameter, over the records of
    :func:`roughgp.experiments.model_check.bootstrap_case` (one synthetic measurement each), and
    the plain check on the same cases beside it.

    Three shares per parameter, each with its 95 % interval
    (:func:`~roughgp.checking.ranks.share_interval`): ``"plain"``, the plain
    check's 0/1 verdicts; ``"calibrated"``, the calibrated check's 0/1 verdicts (tie-breaking
    drawn from the seed); ``"chance"``, their expectation over the tie-breaking draw
    (:func:`~roughgp.checking.calibrated.outside_chance`, the lower-variance
    estimate the verdict on 10 % +- 3 % is given on). Cases whose measured value is not finite
    are left out of that parameter's shares.
    """

    records: tuple
    names: tuple
    n_bootstrap: int
    level: float

    _SETTINGS = ("names", "n_bootstrap", "level", "shape", "n_simulations", "seed")

    @classmethod
    def from_records(cls, records) -> "BootstrapCalibration":
        records = sorted(records, key=lambda r: r["index"])
        if not records:
            raise ValueError("no records")
        head = {k: records[0][k] for k in cls._SETTINGS}
        for r in records:
            if {k: r[k] for k in cls._SETTINGS} != head:
                raise ValueError(f"the records' settings differ: {head} against "
                                 f"{ {k: r[k] for k in cls._SETTINGS} }")
        if len({r["index"] for r in records}) != len(records):
            raise ValueError("a case index occurs twice in the records")
        return cls(tuple(records), tuple(head["names"]), int(head["n_bootstrap"]),
                   float(head["level"]))

    def first(self, n_cases) -> "BootstrapCalibration":
        """The calibration of the ``n_cases`` cases of lowest index."""
        if not 1 <= n_cases <= len(self.records):
            raise ValueError(f"n_cases must be in [1, {len(self.records)}], got {n_cases}")
        return dataclasses.replace(self, records=self.records[:n_cases])

    def values(self, kind) -> np.ndarray:
        """Cases x parameters: ``kind`` ``"plain"`` or ``"calibrated"`` (0/1 verdicts) or
        ``"chance"``; NaN where the measured value is not finite."""
        if kind not in ("plain", "calibrated", "chance"):
            raise ValueError(f"kind must be 'plain', 'calibrated' or 'chance', got {kind!r}")
        chance = np.array([r["chance"] for r in self.records], dtype=np.float64)
        if kind == "chance":
            return chance
        key = "plain_outside" if kind == "plain" else "outside"
        verdicts = np.array([[name in r[key] for name in self.names] for r in self.records],
                            dtype=np.float64)
        return np.where(np.isfinite(chance), verdicts, np.nan)

    def summary(self, tolerance=0.03) -> list:
        """Per parameter a dict: each share (``plain``, ``calibrated``, ``chance``) with its
        ``_low`` and ``_high`` interval bounds, and ``within``: the verdict on
        :attr:`level` +- ``tolerance`` of the chance's interval
        (:func:`~roughgp.checking.ranks.verdict_within`; "too few cases" under
        :data:`MIN_CASES_FOR_VERDICT`)."""
        columns = {kind: self.values(kind) for kind in ("plain", "calibrated", "chance")}
        rows = []
        for i, name in enumerate(self.names):
            row = {"parameter": name}
            for kind, values in columns.items():
                v = values[:, i]
                v = v[np.isfinite(v)]
                row[kind], row[f"{kind}_low"], row[f"{kind}_high"] = (
                    share_interval(v) if v.size > 1
                    else (float(v.mean()) if v.size else np.nan, np.nan, np.nan))
            row["within"] = (verdict_within(row["chance_low"], row["chance_high"], self.level,
                                            tolerance)
                             if len(self.records) >= MIN_CASES_FOR_VERDICT else "too few cases")
            rows.append(row)
        return rows

    def table(self):
        """A pandas DataFrame, a row per parameter: the three shares (%, to 0.1 %, each with its
        95 % interval in parentheses) and the verdict; four columns, narrow enough for a page."""
        import pandas as pd
        rows = self.summary()
        data = {}
        for kind, label in (("plain", "plain check"), ("calibrated", "calibrated check"),
                            ("chance", "calibrated, expected")):
            data[f"{label}, % (95 %)"] = [
                f"{100 * r[kind]:.1f} ({100 * r[kind + '_low']:.1f} to "
                f"{100 * r[kind + '_high']:.1f})" for r in rows]
        data["10 ± 3 %?"] = [r["within"] for r in rows]
        return pd.DataFrame(data, index=pd.Index(self.names, name="parameter"))

    def mean_share(self, kind) -> float:
        """The share of ``kind`` (:meth:`values`) averaged over the parameters."""
        return float(np.mean([r[kind] for r in self.summary()]))

    def outside_ranges(self) -> dict:
        """``{parameter: (measurements, copies)}``: the share of the measurements' plain checks
        that put them outside the range of the simulations (extremeness 0), and the share of
        the bootstrap copies' checks against their refits that put the copies there (the
        calibrated check's yardstick; the same for both where the bootstrap at the fitted model
        imitates the measurement at the true one)."""
        out = {}
        for i, name in enumerate(self.names):
            observed = np.array([r["observed"][i] for r in self.records], dtype=np.float64)
            copies = np.concatenate([np.asarray(r["bootstrap"][i], dtype=np.float64)
                                     for r in self.records])
            out[name] = (float(np.mean(observed[np.isfinite(observed)] == 0)),
                         float(np.mean(copies[np.isfinite(copies)] == 0)))
        return out

    def seconds(self) -> tuple:
        """``(fit, bootstrap)``: the median seconds a case took for its fit and for its
        calibrated check's bootstrap."""
        return (float(np.median([r["fit_seconds"] for r in self.records])),
                float(np.median([r["bootstrap_seconds"] for r in self.records])))


#: the calibrated check's records (``benchmarks/model_check_calibration.py --bootstrap 19``)
BOOTSTRAP_RECORDED = RECORDED.parent / "model_check_bootstrap_64.jsonl"


def load_bootstrap(path=BOOTSTRAP_RECORDED) -> BootstrapCalibration:
    """The :class:`BootstrapCalibration` of the JSONL file ``path``."""
    lines = Path(path).read_text(encoding="utf-8").splitlines()
    return BootstrapCalibration.from_records(json.loads(line) for line in lines if line.strip())


def plot_bootstrap(boot: BootstrapCalibration, ax=None, *, title=None):
    """Per parameter the plain check's share outside and the calibrated check's (its
    expectation over the tie-breaking draw), each with its 95 % interval, on the same cases
    against the fitted model, and the band :attr:`BootstrapCalibration.level` +- 3 %. Returns
    the figure."""
    rows = boot.summary()
    return plot_intervals(boot.names, boot.level,
                           [("plain check", rows, "plain"), ("calibrated check", rows, "chance")],
                           ax, title or f"{len(boot.records)} synthetic measurements against "
                                        f"their fitted model, {boot.n_bootstrap} bootstrap "
                                        f"copies per check")
