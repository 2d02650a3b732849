"""Heights written to a file in the format of its extension (:data:`WRITE_FORMATS`).

``.npy`` (the array), ``.csv`` (text that :func:`roughgp.metrology.measurement.read_measurement`
reads back: a profile as x, z columns, a surface one row per y, the spacing in a comment) and
``.x3p`` (ISO 25178-72, through :func:`roughgp.metrology.x3p.write_x3p`).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from roughgp.metrology.x3p import write_x3p

__all__ = ["WRITE_FORMATS", "check_write_format", "write_heights"]

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


def write_heights(path, z: np.ndarray, spacing, comment: str) -> None:
    """Write heights ``z`` (µm; ``z[ix]`` or ``z[iy, ix]``) with ``spacing`` (µm) in the format
    of the extension (:data:`WRITE_FORMATS`); ``comment`` goes into the file's header."""
    path = check_write_format(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    ext = path.suffix.lower()
    if ext == ".npy":
        np.save(path, z)
    elif ext == ".x3p":
        write_x3p(path, z, spacing, comment=comment)
    elif z.ndim == 1:  # the (x, z) columns that readers.read_profile reads
        with open(path, "w", encoding="utf-8", newline="\n") as out:
            out.write(f"# roughgp profile: x and z in micrometres ({comment})\n"
                      f"# spacing_um: {spacing!r}\n"
                      "x_um,z_um\n")
            np.savetxt(out, np.column_stack((np.arange(z.size) * spacing, z)),
                       fmt="%.12g", delimiter=",")
    else:  # one row per y, columns x: what readers.read_surface reads
        with open(path, "w", encoding="utf-8", newline="\n") as out:
            out.write(f"# roughgp surface: z[iy, ix] in micrometres, one row per y "
                      f"({comment})\n"
                      f"# spacing_um: {spacing!r}\n"
                      f"# shape: {z.shape[0]} {z.shape[1]}\n")
            np.savetxt(out, z, fmt="%.12g", delimiter=",")

