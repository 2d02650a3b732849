"""Heights written to a file in the format of its extension (:data:`WRITE_FORMATS`).

``.npy`` (the array), ``.csv`` (text that :func:`roughgp.io.measurement.read_measurement`
reads back: a profile as x, z columns, a surface one row per y, the spacing in a comment) and
``.x3p`` (ISO 25178-72, through :func:`roughgp.io.x3p.write_x3p`).

Every file is written whole or not at all (:func:`roughgp.common.atomic.atomic_output`): into
a temporary file in the same folder, renamed to its name once complete, so an interrupted
write (Ctrl-C, a full disk, an error) leaves no partial file and an existing file as it was.
The file written is the one named: a ``.npy`` is never given a second extension (``H.NPY``
stays ``H.NPY``).
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np

from roughgp.common.atomic import atomic_output
from roughgp.io.x3p import write_x3p

__all__ = ["WRITE_FORMATS", "atomic_output", "check_write_format", "write_heights"]

#: The formats :func:`write_heights` writes (chosen by the file's extension).
WRITE_FORMATS = (".npy", ".csv", ".x3p")


def check_write_format(path) -> Path:
    """``path`` as a Path if its extension is one of :data:`WRITE_FORMATS` and it is not a
    directory; a ValueError saying which formats there are otherwise."""
    path = Path(path)
    if path.suffix.lower() not in WRITE_FORMATS:
        raise ValueError(f"cannot write {path}: unknown extension "
                         f"{path.suffix or '(none)'!r}; the output formats are "
                         f"{', '.join(WRITE_FORMATS)} (.npy: the height array; .csv: text "
                         f"that fit and texture read back; .x3p: ISO 25178-72)")
    if path.is_dir():
        raise ValueError(f"{path} is a directory; give a file name")
    return path


def _kept(source, spread: bool = False) -> dict:
    """What an input file said that an output keeps: offset, creator, comment (None if not);
    a ``spread`` (an sd, a band's half-width) keeps the x and y offsets, its z offset is 0."""
    source = source or {}
    offset = source.get("offset")
    if offset is not None and (len(offset) != 3 or not np.all(np.isfinite(offset))):
        offset = None
    if offset is not None and spread:
        offset = (*tuple(offset)[:2], 0.0)
    return {"offset": None if offset is None else tuple(float(v) for v in offset),
            "creator": source.get("creator") or None, "comment": source.get("comment") or None}


def write_heights(path, z: np.ndarray, spacing, comment: str, *, source=None,
                  spread: bool = False) -> None:
    """Write heights ``z`` (µm; ``z[ix]`` or ``z[iy, ix]``) with ``spacing`` (µm) in the format
    of the extension (:data:`WRITE_FORMATS`); ``comment`` (what was done: the command and the
    operators applied) goes into the file's header.

    ``source``: the ``meta`` of the input (:class:`roughgp.io.measurement.Measurement`),
    whose offsets (x, y, z of the first point, µm), creator and comment the file keeps: in the
    x3p's own fields (axis offsets, ``Creator``; the input's comment after ``comment``), as
    ``#`` lines of a ``.csv``; a ``.npy`` holds the heights alone. ``spread``: ``z`` is no
    height but a spread about one (a posterior sd, a band's half-width): the input's z
    offset is not added to it (its x and y offsets are kept).
    """
    path = check_write_format(path)
    kept = _kept(source, spread)
    if kept["comment"]:
        comment = f"{comment}; the input's comment: {kept['comment']}"
    comment = _storable(comment)
    with atomic_output(path) as partial:
        _write(partial, path.suffix.lower(), z, spacing, comment, kept)


#: characters XML 1.0 cannot hold (the x3p's comment): the C0 controls but tab, LF and CR
_NOT_XML = re.compile("[\x00-\x08\x0b\x0c\x0e-\x1f\ufffe\uffff]")


def _storable(comment: str) -> str:
    """``comment`` as every format can store it: the bytes of a file name that is not UTF-8
    (surrogate escapes) as ``\\xNN``, characters XML cannot hold as ``?`` (they failed the
    x3p's comment after the work was done)."""
    text = comment.encode("utf-8", "surrogateescape").decode("utf-8", "backslashreplace")
    return _NOT_XML.sub("?", text)


def _write(path: Path, ext: str, z, spacing, comment: str, kept: dict) -> None:
    """:func:`write_heights`'s formats, into ``path`` as named."""
    if ext == ".npy":
        with open(path, "wb") as out:  # a file object: numpy appends no ".npy" to the name
            np.save(out, z)
        return
    if ext == ".x3p":
        write_x3p(path, z, spacing, comment=comment, creator=kept["creator"],
                  offset=kept["offset"])
        return
    lines = "".join(f"# {name}: {value}\n" for name, value in (
        ("creator", kept["creator"]),
        ("offset_um", None if kept["offset"] is None else " ".join(map(repr, kept["offset"]))))
        if value is not None)
    comment = " ".join(comment.split())  # one line
    spacing = float(spacing) if np.ndim(spacing) == 0 else spacing
    with open(path, "w", encoding="utf-8", newline="\n") as out:
        if z.ndim == 1:  # the (x, z) columns that readers.read_profile reads
            out.write(f"# roughgp profile: x and z in micrometres ({comment})\n{lines}"
                      f"# spacing_um: {spacing!r}\n"
                      "x_um,z_um\n")
            np.savetxt(out, np.column_stack((np.arange(z.size) * spacing, z)),
                       fmt="%.12g", delimiter=",")
        else:  # one row per y, columns x: what readers.read_surface reads
            out.write(f"# roughgp surface: z[iy, ix] in micrometres, one row per y "
                      f"({comment})\n{lines}"
                      f"# spacing_um: {spacing!r}\n"
                      f"# shape: {z.shape[0]} {z.shape[1]}\n")
            np.savetxt(out, z, fmt="%.12g", delimiter=",")
