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

__all__ = ["atomic_output", "partial_path", "longest_name"]


def partial_path(path) -> Path:
    """The temporary file :func:`atomic_output` writes ``path`` through: a hidden name in the
    same folder, ``.NAME.<8 hex>.partial`` plus ``path``'s extension."""
    path = Path(path)
    return path.parent / f".{path.name}.{secrets.token_hex(4)}.partial{path.suffix}"


def longest_name(path) -> int:
    """The longest name (bytes) :func:`atomic_output` can give ``path``: the file system's
    limit (255 where it says none) less what the temporary name adds."""
    folder = Path(path).parent
    while not folder.exists() and folder != folder.parent:
        folder = folder.parent
    try:
        limit = os.pathconf(folder, "PC_NAME_MAX")
    except (OSError, ValueError, AttributeError):
        limit = 255
    added = len(os.fsencode(partial_path(path).name)) - len(os.fsencode(Path(path).name))
    return limit - added


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
    partial = partial_path(path)
    try:
        yield partial
        os.replace(partial, path)
    except BaseException:
        with contextlib.suppress(OSError):
            partial.unlink()
        raise
