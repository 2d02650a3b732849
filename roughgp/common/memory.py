"""The host's free memory, without torch: what the size budgets compare against.

:func:`host_free_bytes` is the CPU's side of :func:`roughgp.common.device.free_bytes`; the
modules that never compute through torch (the texture parameters, the command line) ask it
directly, so that reading a file and measuring its texture do not import torch.
"""

from __future__ import annotations

import os

__all__ = ["host_free_bytes"]


def host_free_bytes() -> int:
    """Memory free for new arrays on the host (available physical memory, bytes)."""
    try:
        return os.sysconf("SC_AVPHYS_PAGES") * os.sysconf("SC_PAGE_SIZE")
    except (ValueError, OSError, AttributeError):  # pragma: no cover - non-POSIX
        return 8 * 2**30
