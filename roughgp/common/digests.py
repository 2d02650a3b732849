"""SHA-256 digests of source trees: what a stored result depends on (the ledger's saved run,
the book's notebook cache)."""

from __future__ import annotations

import hashlib
from pathlib import Path

__all__ = ["file_sha256", "source_files", "update_with_files"]


def source_files(path: Path):
    """``path`` itself if it is a file, else every file below it in sorted order, without
    Python bytecode (``__pycache__``, ``.pyc``); nothing if it does not exist."""
    path = Path(path)
    if path.is_file():
        yield path
    elif path.is_dir():
        yield from sorted(p for p in path.rglob("*") if p.is_file()
                          and "__pycache__" not in p.parts and p.suffix != ".pyc")


def update_with_files(digest, files, root: Path) -> None:
    """Feed ``digest`` (a ``hashlib`` object) each file's path relative to ``root`` and the
    SHA-256 of its contents: a renamed, added, removed or edited file changes the digest."""
    for path in files:
        digest.update(str(Path(path).relative_to(root)).encode() + b"\0")
        digest.update(hashlib.sha256(Path(path).read_bytes()).digest())


def file_sha256(path) -> str:
    """The SHA-256 of one file's bytes (hex), read in 1 MiB chunks."""
    digest = hashlib.sha256()
    with open(path, "rb") as handle:
        for chunk in iter(lambda: handle.read(1 << 20), b""):
            digest.update(chunk)
    return digest.hexdigest()
