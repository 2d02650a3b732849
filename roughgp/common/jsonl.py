"""Records kept one JSON object a line (the benchmarks' recorded runs)."""

from __future__ import annotations

import json
from pathlib import Path

from roughgp.common.atomic import atomic_output

__all__ = ["read_records", "write_records"]


def read_records(path) -> list:
    """The JSON objects of the lines of ``path`` (blank lines skipped); none when the file
    does not exist. Raises ValueError naming the file and line of a line that is not JSON."""
    path = Path(path)
    if not path.exists():
        return []
    records = []
    for number, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1):
        if not line.strip():
            continue
        try:
            records.append(json.loads(line))
        except json.JSONDecodeError as error:
            raise ValueError(f"{path}:{number}: not a JSON record ({error.msg})") from None
    return records


def write_records(path, records) -> None:
    """Write ``records`` (JSON-able dicts) to ``path``, one a line, in place of what it held:
    atomically, so an interruption leaves the old file or the new one, never half of it."""
    with atomic_output(path) as partial:
        Path(partial).write_text("".join(json.dumps(r) + "\n" for r in records),
                                 encoding="utf-8")
