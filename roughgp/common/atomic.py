"""Files written whole or not at all: :func:`atomic_output` (a temporary file in the same
folder, renamed over the target when the writing ended normally). Every writer of roughgp
goes through it: heights (:mod:`roughgp.io.writers`), model files
(:meth:`roughgp.surface_models.model.FittedModel.save`), the commands' JSON and plots.
"""

from __future__ import annotations

import contextlib
import os
import secrets
from pathlib import Path

__all__ = ["atomic_output"]


@contextlib.contextmanager
def atomic_output(path):
    """Write ``path`` whole or not at all: yields a temporary path in the same folder (a
    hidden name ending in ``.partial`` plus ``path``'s extension, for writers that pick the
    format by it); when the block ends normally the temporary file is renamed to ``path``
    (``os.replace``: atomic on one file system), when it raises (KeyboardInterrupt too) the
    temporary file is removed and ``path`` is left as it was. Missing folders are made.
    """
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    partial = path.parent / f".{path.name}.{secrets.token_hex(4)}.partial{path.suffix}"
    try:
        yield partial
        os.replace(partial, path)
    except BaseException:
        with contextlib.suppress(OSError):
            partial.unlink()
        raise
