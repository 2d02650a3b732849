"""The creation date written into files (x3p's ``Record2``), reproducible on request."""

from __future__ import annotations

import datetime
import os

__all__ = ["creation_date"]


def creation_date(date=None):
    """The creation date written into ``Record2``: ``date`` (a timezone-aware ``datetime``)
    when given, else the environment variable ``SOURCE_DATE_EPOCH`` (whole seconds since
    1970-01-01 UTC, the reproducible-builds convention) when set, else the current UTC time.
    The same heights with the same date give a byte-identical file."""
    if date is not None:
        if not isinstance(date, datetime.datetime) or date.tzinfo is None:
            raise ValueError(f"date must be a timezone-aware datetime.datetime, got {date!r}")
        return date
    epoch = os.environ.get("SOURCE_DATE_EPOCH", "").strip()
    if not epoch:
        return datetime.datetime.now(datetime.timezone.utc)
    if not epoch.isdigit() or int(epoch) > 253402300799:  # up to 9999-12-31T23:59:59Z
        raise ValueError(f"SOURCE_DATE_EPOCH must be whole seconds since 1970-01-01 UTC "
                         f"(0 to 253402300799), got {epoch!r}")
    return datetime.datetime.fromtimestamp(int(epoch), datetime.timezone.utc)
