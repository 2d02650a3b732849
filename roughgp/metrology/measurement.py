"""A measurement read from a file, whatever its format: heights in µm and where the spacing
came from.

:func:`read_measurement` dispatches on the extension (:data:`READ_FORMATS`) to the readers of
:mod:`roughgp.metrology.readers`; :class:`Measurement` holds ``z`` (``z[ix]`` or ``z[iy, ix]``,
NaN where unmeasured), ``spacing`` in array order and how the spacing was found.
:func:`mean_profile` reduces a surface to its mean profile (section 3.3 fits a profile).
"""

from __future__ import annotations

import dataclasses
import math
import re
from pathlib import Path

import numpy as np

from roughgp.metrology import readers
from roughgp.metrology.readers import MalformedFileError

__all__ = ["Measurement", "READ_FORMATS", "read_measurement", "mean_profile"]

#: The formats :func:`read_measurement` reads (by the file's extension).
READ_FORMATS = (".npy", ".csv", ".txt", ".dat", ".xyz", ".x3p")

_GIVEN = "as given (--spacing)"  # the spacing source when the caller gives the spacing


@dataclasses.dataclass
class Measurement:
    """Heights read from a file: ``z`` in µm (``z[ix]`` or ``z[iy, ix]``), ``spacing`` in
    array order (``(dx,)`` or ``(dy, dx)``, µm), and where the spacing came from."""

    z: np.ndarray
    spacing: tuple
    spacing_source: str

    @property
    def kind(self) -> str:
        """``"profile"`` (1-D) or ``"surface"`` (2-D)."""
        return "profile" if self.z.ndim == 1 else "surface"


def _check_input(path) -> Path:
    p = Path(path)
    if not p.exists():
        raise FileNotFoundError(2, "no such file", str(path))
    if not p.is_file():
        raise ValueError(f"not a file: {path}")
    if p.suffix.lower() not in READ_FORMATS:
        raise ValueError(f"cannot read {path}: unknown extension {p.suffix or '(none)'!r}; "
                         f"the formats read are {', '.join(READ_FORMATS)}")
    return p


def _csv_header(path: Path) -> tuple[str | None, float | None]:
    """What a CSV written by ``roughgp simulate`` says about itself in its comment lines:
    ``(kind, spacing)``, each None when not said."""
    kind = spacing = None
    with open(path, encoding="utf-8-sig", errors="replace") as stream:
        for _, line in zip(range(20), stream):
            if not line.startswith("#"):
                break
            m = re.match(r"#\s*roughgp (profile|surface)\b", line)
            kind = m.group(1) if m else kind
            m = re.match(r"#\s*spacing_um:\s*([^\s,;]+)", line)
            if m:
                try:
                    spacing = float(m.group(1))
                except ValueError:
                    pass
    return kind, spacing


def _profile_spacing(x: np.ndarray, path: Path) -> float:
    """The step of a profile's x column; a clear error unless it is regular."""
    steps = np.diff(x)
    step = float((x[-1] - x[0]) / (x.size - 1))
    if np.max(np.abs(steps - step)) > 1e-6 * step:
        raise MalformedFileError(f"{path}: the x column is not a regular grid (steps from "
                                 f"{steps.min():.6g} to {steps.max():.6g}); roughgp needs "
                                 "equally spaced points")
    return step



def read_measurement(path, *, kind: str = "auto", spacing: float | None = None) -> Measurement:
    """Read a profile or a surface (heights in um) from any of :data:`READ_FORMATS`.

    ``kind`` forces "profile" or "surface" for text tables; ``spacing`` (um) overrides the
    file's own (x3p, xyz, a profile's x column, the comment of a ``roughgp simulate`` CSV);
    without either it is 1 µm. A missing file raises ``FileNotFoundError``; a file that is
    not what its extension says, :class:`~roughgp.metrology.readers.MalformedFileError`.
    """
    path = _check_input(path)
    if spacing is not None and not (math.isfinite(spacing) and spacing > 0):
        raise ValueError(f"spacing must be > 0 (um), got {spacing!r}")
    ext = path.suffix.lower()
    if ext == ".npy":
        with open(path, "rb") as stream:
            if stream.read(6) != b"\x93NUMPY":
                raise readers.MalformedFileError(f"{path}: not a .npy file (no NumPy header)")
        try:
            z = np.load(path, allow_pickle=False)
        except (ValueError, OSError, EOFError) as exc:
            raise readers.MalformedFileError(f"{path}: not a readable .npy array ({exc})") \
                from None
        if z.ndim == 2 and z.shape[0] == 1 and kind != "surface":
            z = z[0]
        if z.ndim not in (1, 2) or not np.issubdtype(z.dtype, np.number):
            raise readers.MalformedFileError(f"{path}: expected a numeric profile (1-D) or "
                                             f"surface (2-D), got {z.dtype} of shape "
                                             f"{z.shape}")
        z = np.asarray(z, dtype=np.float64)
        d = 1.0 if spacing is None else spacing
        source = (_GIVEN if spacing is not None
                  else "assumed: a .npy file stores none; give --spacing")
        return Measurement(z, (d,) * z.ndim, source)
    if ext == ".x3p":
        hm = readers.read_x3p(path)
        if spacing is not None:
            return Measurement(hm.z, (spacing,) * hm.z.ndim, _GIVEN + ", not the file's")
        return Measurement(hm.z, tuple(hm.spacing), "from the x3p file")
    if ext == ".xyz":
        z, (dy, dx) = readers.read_xyz(path)
        if spacing is not None:
            return Measurement(z, (spacing, spacing), _GIVEN + ", not the file's")
        return Measurement(z, (dy, dx), "from the x y positions")

    # text tables: a roughgp CSV says what it is; otherwise 1 or 2 columns are a profile
    header_kind, header_spacing = _csv_header(path)
    table, _ = readers.read_surface(path, spacing=1.0)
    if kind == "auto":
        kind = header_kind or ("profile" if table.shape[1] <= 2 else "surface")
    if spacing is not None:
        step, source = spacing, _GIVEN
    elif header_spacing is not None:
        step, source = header_spacing, "from the file's spacing_um comment"
    else:
        step, source = 1.0, "assumed: the file states none; give --spacing"
    if kind == "surface":
        return Measurement(table, (step, step), source)
    if table.shape[1] == 1:  # heights only
        _, z = readers.read_profile(path, spacing=step)
        return Measurement(z, (step,), source)
    x, z = readers.read_profile(path)  # x, z columns
    if spacing is None:
        step, source = _profile_spacing(x, path), "from the x column"
    return Measurement(z, (step,), source)




def mean_profile(heights: Measurement, axis: str = "x") -> tuple[np.ndarray, float, str]:
    """A profile ``(z, spacing, how)`` from a profile (as read) or a surface: its mean profile
    along ``axis`` (``"x"``: the rows averaged; ``"y"``: the columns), NaN points ignored."""
    if axis not in ("x", "y"):
        raise ValueError(f"axis must be 'x' or 'y', got {axis!r}")
    if heights.kind == "profile":
        return heights.z, heights.spacing[0], "the profile as read"
    z = heights.z
    if axis == "x":
        profile, spacing = np.nanmean(z, axis=0), heights.spacing[1]
        how = (f"mean profile along x: the {z.shape[0]} rows averaged (over y, along the lay "
               "of feed marks that run along y)")
    else:
        profile, spacing = np.nanmean(z, axis=1), heights.spacing[0]
        how = f"mean profile along y: the {z.shape[1]} columns averaged (over x)"
    return profile, spacing, how

