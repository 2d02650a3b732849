"""Where a model's data came from: the file, its SHA-256, the reader and the spacing's source
(beyond the paper). ``fit_surface_model(..., data=provenance.of_file(path, measurement))`` keeps
it in the model file, as ``roughgp fit`` does."""

from __future__ import annotations

from pathlib import Path

from roughgp.common.digests import file_sha256

__all__ = ["of_file"]


def of_file(path, measurement=None) -> dict:
    """``{"file", "sha256"[, "reader", "spacing_from"]}`` of the measurement file ``path``
    (``measurement``: its :class:`~roughgp.io.measurement.Measurement`, for the reader
    and where the spacing came from)."""
    record = {"file": Path(path).name, "sha256": file_sha256(path)}
    if measurement is not None:
        record.update(reader=measurement.reader, spacing_from=measurement.spacing_source)
    return record
