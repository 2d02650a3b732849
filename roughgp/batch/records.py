"""The plan of a batch and each file's record: what makes a batch's results independent of the
order and the number of workers, and a rerun resume where the last one stopped.

* :class:`Plan`: the steps and their options (JSON-ready), and its digest (:meth:`Plan.digest`);
* :func:`file_seed`: each file's seed, from the user's seed and the file's SHA-256, never from
  the order in which the files run;
* :func:`record_name`: where a file's record and artefacts go in the output folder (from its
  name and path, so that two files of one name in two folders do not meet);
* :func:`write_record` (atomic: a temporary file renamed, so an interrupted batch leaves only
  complete records) and :func:`current_record` (the resume rule: a record is reused when it is
  complete and current: the same file hash, the same plan, the same roughgp version, and no
  error; a failed file is tried again).
"""

from __future__ import annotations

import dataclasses
import hashlib
import json
import os
import re
from pathlib import Path

from roughgp.common.atomic import atomic_output
from roughgp.common.json_values import plain
from roughgp.common.version import VERSION

__all__ = ["STEPS", "Plan", "file_seed", "record_name", "write_record", "read_record",
           "current_record", "RECORD_FORMAT"]

#: The steps a batch can run on each file, in the order they run.
STEPS = ("texture", "fit", "check", "fill", "simulate")

#: The version of the record's layout (a record of another layout is not current).
RECORD_FORMAT = 1


@dataclasses.dataclass(frozen=True)
class Plan:
    """What a batch does to each file: ``steps`` (a subset of :data:`STEPS`, run in that
    order), the user's ``seed`` (each file's own is :func:`file_seed`) and ``options``: a dict
    of dicts, one per step, plus ``"read"`` (the reader's options: ``kind``, ``spacing``,
    ``channel``, ``unit``), each holding the keyword arguments of the library call that step
    makes (JSON values only)."""

    steps: tuple
    seed: int = 0
    options: dict = dataclasses.field(default_factory=dict)

    def __post_init__(self):
        unknown = [s for s in self.steps if s not in STEPS]
        if unknown:
            raise ValueError(f"unknown step {unknown[0]!r}: the steps are {', '.join(STEPS)}")
        if not self.steps:
            raise ValueError(f"no step: give one or more of {', '.join(STEPS)}")
        for step, needs in (("check", "fit"), ("simulate", "fit")):
            if step in self.steps and needs not in self.steps:
                raise ValueError(f"the step {step} needs the step {needs} (its model)")
        object.__setattr__(self, "steps", tuple(s for s in STEPS if s in self.steps))

    def of(self, step: str) -> dict:
        """The options of ``step`` (``"read"`` too)."""
        return dict(self.options.get(step, {}))

    def to_dict(self) -> dict:
        return {"steps": list(self.steps), "seed": self.seed, "options": self.options}

    def digest(self) -> str:
        """The SHA-256 of the plan (its JSON, keys sorted): a record made under another plan
        is not current."""
        text = json.dumps(self.to_dict(), sort_keys=True, default=str)
        return hashlib.sha256(text.encode()).hexdigest()


def file_seed(seed: int, sha256: str) -> int:
    """The seed of one file: the first 4 bytes of SHA-256(``"<seed>:<file's sha256>"``), an
    integer in [0, 2^32 - 1]. It depends on the user's seed and the file's bytes only: the
    same whatever the order of execution or the number of workers, different for two files
    (unless they are the same bytes)."""
    digest = hashlib.sha256(f"{int(seed)}:{sha256}".encode()).digest()
    return int.from_bytes(digest[:4], "big")


def record_name(path) -> str:
    """The name of a file's record (``NAME.json``) and artefact folder (``NAME/``): the file's
    name (characters other than letters, digits, ``.-_`` replaced by ``_``) and the first 8 hex
    digits of the SHA-256 of its absolute path."""
    path = Path(path)
    stem = re.sub(r"[^A-Za-z0-9._-]", "_", path.name)[:80]
    where = hashlib.sha256(os.path.abspath(path).encode()).hexdigest()[:8]
    return f"{stem}-{where}"


def write_record(path, record: dict) -> None:
    """Write ``record`` as JSON to ``path``, whole or not at all (a temporary file renamed:
    an interrupted batch leaves no partial record)."""
    text = json.dumps(plain(record), indent=1, sort_keys=False) + "\n"
    with atomic_output(path) as partial:
        Path(partial).write_text(text, encoding="utf-8")


def read_record(path):
    """The record at ``path``, or None where there is none or it cannot be read."""
    try:
        record = json.loads(Path(path).read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return None
    return record if isinstance(record, dict) else None


def current_record(path, sha256: str, plan: Plan):
    """The record at ``path`` if it is complete and current: the same file hash, the same plan
    (its digest), the same roughgp version and record layout, and no error; else None (the
    file is run again)."""
    record = read_record(path)
    if record is None:
        return None
    if (record.get("sha256") != sha256 or record.get("plan_digest") != plan.digest()
            or record.get("roughgp_version") != VERSION
            or record.get("record_format") != RECORD_FORMAT
            or record.get("status") != "done"):
        return None
    return record
