"""Values made ready for JSON, one way for every file the project writes: a model file
(:meth:`roughgp.surface_models.model.FittedModel.save`), a batch record and its table
(:mod:`roughgp.batch.records`, :mod:`roughgp.batch.table`) and a command's ``--json`` output
(:mod:`roughgp.cli.output`)."""

from __future__ import annotations

import math

__all__ = ["plain"]


def plain(value, *, nan_as_null: bool = True):
    """``value`` with every dict, list, tuple, numpy array and numpy scalar in it made plain
    JSON: dicts with string keys, lists, Python numbers. A NaN or infinite float becomes None
    (JSON's null) with ``nan_as_null``, else it is kept (a model file writes NaN)."""
    if isinstance(value, dict):
        return {str(k): plain(v, nan_as_null=nan_as_null) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [plain(v, nan_as_null=nan_as_null) for v in value]
    if hasattr(value, "tolist") and not isinstance(value, (str, bytes)):  # numpy, torch
        return plain(value.tolist(), nan_as_null=nan_as_null)
    if nan_as_null and isinstance(value, float) and not math.isfinite(value):
        return None
    return value
