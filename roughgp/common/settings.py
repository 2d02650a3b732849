"""Run-size switch shared by the chapters, the ledger and the experiments: quick by default,
the paper's sizes on request. One rule decides: an explicit ``full`` (``True`` / ``False``, as
``roughgp reproduce --full`` passes it) wins; ``full=None`` means the environment variable
``ROUGHGP_FULL=1`` (for example ``ROUGHGP_FULL=1 make book``), off by default so CI stays quick.
"""

from __future__ import annotations

import os

__all__ = ["full_size", "resolve_full", "pick"]


def full_size() -> bool:
    """True when ``ROUGHGP_FULL`` is set to 1 (or true/yes)."""
    return os.environ.get("ROUGHGP_FULL", "").strip().lower() in {"1", "true", "yes"}


def resolve_full(full=None) -> bool:
    """The rule: ``full`` when given (``True`` / ``False``), else :func:`full_size`."""
    return full_size() if full is None else bool(full)


def pick(quick, full_value, *, full=None):
    """``full_value`` at full size (:func:`resolve_full` of ``full``), else ``quick``."""
    return full_value if resolve_full(full) else quick
