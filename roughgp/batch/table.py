"""A batch's records as one tidy table: one row per file, one column per quantity
(:func:`rows`), written as CSV and, where pyarrow is installed, Parquet (:func:`write_table`).

The columns, in this order: ``path``, ``sha256``, ``status`` (``done`` or ``failed``),
``error``, ``seed`` (the file's, :func:`roughgp.batch.records.file_seed`), ``reader``,
``kind``, ``ny``, ``nx`` (``nx`` alone for a profile), ``spacing_y_um``, ``spacing_x_um``,
``unit``, ``missing``; with ``--spurious``, ``spurious.flagged`` (the points found spurious and
left unmeasured) and ``spurious.converged``; then every ISO parameter by its symbol (``Sq``,
``Sal``, ... or ``Ra``, ``Rq``, ...: heights and lengths in µm, ``Std`` in degrees, material
ratios in percent); the model's ``model`` (the rung: ``eq18``, ``eq18-matern``, ``sm2d``,
``measured-psd``, ``eq21``), ``model_chosen`` (``--model auto``), ``marginal`` and its
hyperparameters as ``fit.NAME`` (lists as JSON text), ``model_file``, ``part`` (the half
fitted, ``--part``); the check's ``check_outside`` (the parameters outside the simulated range,
comma-separated), ``check_count`` (how many) and, per parameter, ``check.NAME.rank`` and
``check.NAME.outside`` (with ``--part``: on the fitted half; the same columns ``held_out*`` on
the other half), ``check_simulations`` (``predictive (refits)``, ``predictive (sandwich)`` or
``predictive (tiles)`` with ``--predictive``; empty: plug-in); ``filled``, ``filled_file``,
``simulated_file``; the timings ``seconds.STEP`` and ``seconds.total``. A column a file does not
have is empty (null).
"""

from __future__ import annotations

import csv
import io
import json
from pathlib import Path

from roughgp.common.atomic import atomic_output
from roughgp.common.json_values import plain

__all__ = ["rows", "columns", "write_table", "read_csv_table", "parquet_available"]

_HEAD = ("path", "sha256", "status", "error", "seed", "reader", "kind", "ny", "nx",
         "spacing_y_um", "spacing_x_um", "unit", "missing")


def _row(record: dict) -> dict:
    row = {k: record.get(k) for k in ("path", "sha256", "status", "error", "seed", "reader",
                                      "kind", "unit", "missing")}
    shape, spacing = record.get("shape") or [], record.get("spacing_um") or []
    if len(shape) == 2:
        row.update(ny=shape[0], nx=shape[1], spacing_y_um=spacing[0], spacing_x_um=spacing[1])
    elif len(shape) == 1:
        row.update(nx=shape[0], spacing_x_um=spacing[0] if spacing else None)
    spurious = record.get("spurious")
    if spurious:
        row.update({"spurious.flagged": spurious.get("flagged"),
                    "spurious.converged": spurious.get("converged")})
    texture = record.get("texture") or {}
    row.update(texture.get("parameters", {}))
    fit = record.get("fit")
    if fit:
        row.update(model=fit.get("equation"), model_chosen=fit.get("chosen"),
                   marginal=fit.get("marginal"))
        for name, value in fit.get("hyperparameters", {}).items():
            row[f"fit.{name}"] = (json.dumps(value) if isinstance(value, (list, dict))
                                  else value)
        row["model_file"] = fit.get("model_file")
    if fit and fit.get("part"):
        row["part"] = fit["part"].get("name")
    for key in ("check", "held_out"):
        check = record.get(key)
        if check:
            row[f"{key}_outside"] = ",".join(check.get("outside", []))
            row[f"{key}_count"] = len(check.get("outside", []))
            for name, p in check.get("parameters", {}).items():
                row[f"{key}.{name}.rank"] = p.get("rank")
                row[f"{key}.{name}.outside"] = p.get("outside")
    predictive = (record.get("check") or {}).get("predictive")
    if predictive:
        row["check_simulations"] = f"predictive ({predictive.get('from')})"
    fill = record.get("fill")
    if fill:
        row.update(filled=fill.get("filled"), filled_file=fill.get("file"))
    simulate = record.get("simulate")
    if simulate:
        row["simulated_file"] = simulate.get("file")
    for step, seconds in (record.get("seconds") or {}).items():
        row[f"seconds.{step}"] = seconds
    return row


def rows(records) -> list[dict]:
    """One row (a flat dict) per record, in the order given: a record as its JSON file holds
    it (:func:`~roughgp.common.json_values.plain`: lists, not numpy arrays; NaN as null), so
    that the rows of this run's records and of records read back from an earlier run are
    the same."""
    return [_row(plain(r)) for r in records]


def columns(table: list[dict]) -> list[str]:
    """The columns of ``table``: :data:`_HEAD` first, then the others in the order they first
    appear, the timings last."""
    seen = list(_HEAD)
    for row in table:
        for key in row:
            if key not in seen:
                seen.append(key)
    timing = [c for c in seen if c.startswith("seconds.")]
    return [c for c in seen if c not in timing] + timing


def parquet_available() -> bool:
    """Whether pyarrow is installed (the Parquet table needs it; the CSV does not)."""
    try:
        import pyarrow  # noqa: F401
        import pyarrow.parquet  # noqa: F401
    except ImportError:
        return False
    return True


def _cell(value):
    if value is None:  # NaN too: :func:`rows` made it null
        return ""
    if isinstance(value, float):
        return repr(value)  # every digit: the table reads back number for number
    return str(value)


def write_table(records, folder, name="table") -> list[Path]:
    """Write the records' table as ``folder/NAME.csv`` and, where pyarrow is installed,
    ``folder/NAME.parquet``, each whole or not at all; returns the paths written."""
    table = rows(records)
    names = columns(table)
    folder = Path(folder)
    text = io.StringIO()
    writer = csv.writer(text, lineterminator="\n")
    writer.writerow(names)
    for row in table:
        writer.writerow([_cell(row.get(c)) for c in names])
    written = [folder / f"{name}.csv"]
    with atomic_output(written[0]) as partial:
        Path(partial).write_text(text.getvalue(), encoding="utf-8")
    if parquet_available():
        import pyarrow as pa
        import pyarrow.parquet as pq
        arrays = {}
        for c in names:
            values = [row.get(c) for row in table]
            kinds = {type(v) for v in values if v is not None}
            if kinds == {int, float}:
                values = [None if v is None else float(v) for v in values]
            elif len(kinds) > 1:
                values = [None if v is None else str(v) for v in values]
            arrays[c] = pa.array(values) if kinds else pa.array(values, type=pa.string())
        path = folder / f"{name}.parquet"
        with atomic_output(path) as partial:
            pq.write_table(pa.table(arrays), partial)
        written.append(path)
    return written


def read_csv_table(path) -> list[dict]:
    """The rows of a table's CSV as dicts of strings (for tests and quick looks; pandas reads
    it as ``pandas.read_csv(path)``)."""
    with open(path, newline="", encoding="utf-8") as handle:
        return list(csv.DictReader(handle))
