"""The real maps of ``data/`` out of sample: each model fitted on one half of a map, checked on
that half and on the other half, which it did not see (issue 40, the data's verdict).

A researcher who measures part of a surface wants new surfaces like *the surface*. Each map of
:data:`~roughgp.experiments.real_maps.REAL_MAPS` is cut to its central window of at most
:data:`LONG` points along its longer axis and :data:`SHORT` along the other
(:func:`split_window`), and the window is halved along its longer axis: half A (``left`` or
``top``) is fitted, half B is held out. The run goes through ``roughgp batch --part A --steps
fit,check`` with each model of :data:`MODELS`, exactly as a user would run it, so each row is
what the single commands ``fit ground --part`` and ``check --held-out`` give (19 simulations,
the batch's per-file seed). ``benchmarks/real_out_of_sample.py`` runs it and records the rows
in :data:`RECORDED`; :func:`summary` counts, per model, the maps with at most :data:`PASS`
parameters of 13 outside on each half.

The issue's target is at least 80 % of the maps with at most 2 outside on the held-out half
for the best model. "Best" is read here per model, chosen before looking at B: the share of
maps each model passes. The best in hindsight (the model with the fewest outside on B, per
map) is also shown, labelled as what it is: an upper bound, since it chooses on the held-out
half itself.
"""

from __future__ import annotations

import dataclasses
import datetime
from pathlib import Path

import numpy as np

from roughgp.checking.auto_choice import central_window
from roughgp.common.jsonl import read_records
from roughgp.experiments.real_maps import REAL_MAPS

__all__ = ["LONG", "SHORT", "PASS", "MODELS", "RECORDED", "WINDOWS_DATE", "Model", "split_window",
           "write_windows", "row_of", "load_rows", "summary", "per_map", "sq_ratio", "sq_spans",
           "outside_by_parameter"]

LONG, SHORT = 512, 256  #: the window: at most 512 points along the longer axis, 256 across
PASS = 2  #: at most this many of 13 outside: the model reproduces that half
RECORDED = Path(__file__).resolve().parents[2] / "benchmarks" / "results" / \
    "real_out_of_sample.jsonl"


@dataclasses.dataclass(frozen=True)
class Model:
    """A model of the run: its name in the tables and its ``roughgp batch`` options."""

    name: str
    options: tuple
    about: str

    @property
    def spurious(self) -> bool:
        """Whether the run leaves out the spurious points (``--spurious``)."""
        return "--spurious" in self.options



MODELS = (
    Model("eq18", ("--model", "eq18", "--likelihood", "whittle"),
          "the paper's eq 18, Gaussian heights, fitted by the Whittle likelihood"),
    Model("eq18-sandwich", ("--model", "eq18", "--likelihood", "whittle", "--predictive", "19",
                            "--predictive-from", "sandwich"),
          "eq 18 as above, its simulations' parameters drawn from the fit's sandwich "
          "covariance (the fit's uncertainty carried)"),
    Model("auto", ("--model", "auto"),
          "the ladder's choice (fit ground --model auto): the rung by held-out prediction, "
          "its heights by the out-of-sample check on the fitted half's own halves"),
    Model("sm-iaaft", ("--model", "sm", "--marginal", "iaaft"),
          "2-D spectral mixture, the measured heights (IAAFT)"),
    Model("psd-iaaft", ("--model", "psd", "--marginal", "iaaft"),
          "the measured PSD, the measured heights (IAAFT)"),
    Model("psd-iaaft-spurious", ("--spurious", "--model", "psd", "--marginal", "iaaft"),
          "psd-iaaft with the window's spurious points (spikes, pits) found by the GP and "
          "left unmeasured in the fit and both checks (batch --spurious)"),
    Model("psd-iaaft-tiles", ("--model", "psd", "--marginal", "iaaft", "--predictive", "19",
                              "--predictive-from", "tiles"),
          "psd-iaaft, its simulations drawn from 19 models given the variance, heights and "
          "spectrum's shape of half A's 4 x 4 tiles drawn with replacement "
          "(roughgp.checking.tile_bootstrap)"),
    Model("population", ("--model", "population", "--anchors", "2", "2"),
          "eq 18 per tile of half A (2 x 2), pooled by random effects; each simulation a new "
          "region"),
)


#: the names of the models run with ``--spurious``
_SPURIOUS = frozenset(m.name for m in MODELS if m.spurious)


def split_window(shape) -> tuple:
    """``(first row, first column, rows, columns, part)``: the central window of a map of
    ``shape`` (at most :data:`LONG` points along its longer axis, :data:`SHORT` across) and
    the half fitted, ``"left"`` when the window is at least as wide as tall, else ``"top"``
    (:func:`roughgp.checking.auto_choice.central_window`, the window ``--model auto`` checks
    its heights on)."""
    return central_window(shape, LONG, SHORT)


#: the creation date written into every window: a window's bytes, and with them its seed in
#: the batch (:func:`roughgp.batch.records.file_seed`), then depend on the map alone (windows
#: written with the date of the day gave each fresh ``--work`` folder other seeds, and
#: ``--model auto`` other rungs on some maps)
WINDOWS_DATE = datetime.datetime(2026, 12, 1, tzinfo=datetime.timezone.utc)


def write_windows(folder, maps=REAL_MAPS) -> dict:
    """Write each map's :func:`split_window` as ``folder/NAME.x3p`` (its spacing kept, the date
    :data:`WINDOWS_DATE`); return ``{part: [paths]}``, the windows grouped by the half
    fitted."""
    from roughgp.io.measurement import read_measurement
    from roughgp.io.x3p import write_x3p
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    groups: dict = {}
    for entry in maps:
        m = read_measurement(entry.path)
        r0, c0, rows, cols, part = split_window(m.z.shape)
        path = folder / (entry.name.replace(".", "_") + ".x3p")
        if not path.exists():
            write_x3p(path, m.z[r0:r0 + rows, c0:c0 + cols], m.spacing,
                      comment=f"{entry.name}: rows {r0}:{r0 + rows}, columns {c0}:{c0 + cols}",
                      date=WINDOWS_DATE)
        groups.setdefault(part, []).append(path)
    return groups


def row_of(model: str, record: dict) -> dict:
    """One recorded row from a batch record: the map, the model, the parameters outside on
    each half, the rung fitted (``auto``: the rung chosen and its heights), the timings or the
    error."""
    fit = record.get("fit") or {}
    inside, held = record.get("check") or {}, record.get("held_out") or {}
    name = Path(record["path"]).stem
    for entry in REAL_MAPS:
        if entry.name.replace(".", "_") == name:
            name = entry.name
    return {"map": name, "model": model, "shape": record.get("shape"),
            "sha256": record.get("sha256"), "seed": record.get("seed"),
            "rung": fit.get("rung"), "chosen": fit.get("chosen"), "heights": fit.get("heights"),
            "fitted_outside": inside.get("outside"), "held_out_outside": held.get("outside"),
            "sq_um": [_measured(inside, "Sq"), _measured(held, "Sq")],
            "held_out_sq_range_um": _simulated_range(held, "Sq"),
            "spurious_flagged": (record.get("spurious") or {}).get("flagged"),
            "seconds": (record.get("seconds") or {}).get("total"),
            "error": record.get("error")}


def _measured(check: dict, name: str):
    return ((check.get("parameters") or {}).get(name) or {}).get("measured")


def _simulated_range(check: dict, name: str):
    """``[lowest, highest]`` of the simulations' ``name`` in a check's record, else None."""
    entry = (check.get("parameters") or {}).get(name) or {}
    low, high = entry.get("low"), entry.get("high")
    return None if low is None or high is None else [low, high]


def sq_spans(rows, model) -> "pandas.DataFrame":
    """Per map of ``model``'s rows that recorded it: how far the held-out half's Sq lies from
    the fitted half's (``|log(Sq B / Sq A)|``) and how widely the simulations' Sq spreads on
    the held-out half (``log(highest / lowest)`` of the 19), both in the same log units. The
    simulations of a model fitted on A are centred near A's Sq: a distance beyond about half
    their spread puts B's Sq outside."""
    import pandas as pd
    lines = {}
    for r in rows:
        span = r.get("held_out_sq_range_um")
        a, b = r.get("sq_um") or (None, None)
        if r["model"] == model and span and a and b and min(span) > 0:
            lines[r["map"]] = {"halves apart": abs(float(np.log(b / a))),
                               "simulations' spread": float(np.log(span[1] / span[0]))}
    return pd.DataFrame.from_dict(lines, orient="index")


def load_rows(path=RECORDED) -> list:
    """The recorded rows (one per map and model)."""
    return read_records(path)


def _count(outside):
    return np.nan if outside is None else len(outside)


def per_map(rows) -> "pandas.DataFrame":
    """Maps by models: ``"A / B"``, the parameters outside on the fitted half and on the
    held-out half (``refused`` where the model was not fitted)."""
    import pandas as pd
    table = {}
    for r in rows:
        cell = ("refused" if r["error"] else
                f"{_count(r['fitted_outside'])} / {_count(r['held_out_outside'])}")
        table.setdefault(r["map"], {})[r["model"]] = cell
    order = [m.name for m in MODELS if any(r["model"] == m.name for r in rows)]
    frame = pd.DataFrame.from_dict(table, orient="index")[order]
    frame.insert(0, "Sq B / A", [sq_ratio(rows, name) for name in frame.index])
    return frame


def sq_ratio(rows, name) -> float:
    """The measured Sq of the held-out half over the fitted half's for the map ``name`` (the
    same for every model run on the heights as measured: the halves' own roughness; the runs
    with ``--spurious`` measure the halves without their spurious points), NaN where no check
    recorded it."""
    for r in rows:
        a, b = r.get("sq_um") or (None, None)
        if r["map"] == name and a and b and r["model"] not in _SPURIOUS:
            return float(b) / float(a)
    return np.nan


def outside_by_parameter(rows, half="held_out") -> "pandas.DataFrame":
    """Parameters by models: on how many maps each parameter is outside on ``half``
    (``"held_out"``: B, ``"fitted"``: A)."""
    import pandas as pd
    from roughgp.checking.model_check import SURFACE_PARAMETERS
    counts = {}
    for r in rows:
        for name in r[f"{half}_outside"] or ():
            counts.setdefault(r["model"], {}).setdefault(name, 0)
            counts[r["model"]][name] += 1
    order = [m.name for m in MODELS if any(r["model"] == m.name for r in rows)]
    return pd.DataFrame({m: [counts.get(m, {}).get(p, 0) for p in SURFACE_PARAMETERS]
                         for m in order}, index=list(SURFACE_PARAMETERS))


def summary(rows) -> "pandas.DataFrame":
    """Per model: the maps it was run on, those fitted (not refused), and the share of the maps
    run with at most :data:`PASS` outside on the fitted half and on the held-out half (a
    refused map counts as not reproduced), the mean count outside on each. The row ``best in
    hindsight`` takes per map the model run on the heights as measured with the fewest outside
    on the held-out half: an upper bound, since it chooses on that half; ``best in hindsight,
    spurious left out`` the same among the runs with ``--spurious``, where there are any."""
    import pandas as pd
    lines = []

    def line(name, chosen):
        fitted = [r for r in chosen if not r["error"]]
        a = np.array([_count(r["fitted_outside"]) for r in fitted], float)
        b = np.array([_count(r["held_out_outside"]) for r in fitted], float)
        n = len(chosen)
        lines.append({"model": name, "maps": n, "fitted": len(fitted),
                      "A: ≤ 2 outside": float(np.sum(a <= PASS)) / n if n else np.nan,
                      "B: ≤ 2 outside": float(np.sum(b <= PASS)) / n if n else np.nan,
                      "A: mean outside": float(np.mean(a)) if a.size else np.nan,
                      "B: mean outside": float(np.mean(b)) if b.size else np.nan})

    for m in MODELS:
        chosen = [r for r in rows if r["model"] == m.name]
        if chosen:
            line(m.name, chosen)
    for label, left_out in (("best in hindsight", False),
                            ("best in hindsight, spurious left out", True)):
        best = []
        for name in sorted({r["map"] for r in rows}):
            fitted = [r for r in rows if r["map"] == name and not r["error"]
                      and (r["model"] in _SPURIOUS) == left_out]
            if fitted:
                best.append(min(fitted, key=lambda r: _count(r["held_out_outside"])))
        if best:
            line(label, best)
    return pd.DataFrame(lines)
