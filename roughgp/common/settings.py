"""Run-size switch shared by the chapters: quick by default, the paper's sizes on request.

Set the environment variable ``ROUGHGP_FULL=1`` (for example ``ROUGHGP_FULL=1 make book``)
to run every chapter at the paper's full sizes; the default keeps CI quick.
"""

from __future__ import annotations

import os

__all__ = ["full_size", "pick"]


def full_size() -> bool:
    """True when ``ROUGHGP_FULL`` is set to 1 (or true/yes)."""
    return os.environ.get("ROUGHGP_FULL", "").strip().lower() in {"1", "true", "yes"}


def pick(quick, full):
    """``full`` when :func:`full_size` is on, else ``quick``."""
    return full if full_size() else quick
