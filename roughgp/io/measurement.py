"""A measurement read from a file, whatever its format: heights in µm, the spacing, and where
each came from.

:func:`read_measurement` picks the reader by the extension and, where the extension is
ambiguous (``.txt``, ``.csv``, ``.dat``, ``.asc``), by the content: text tables go to
:mod:`roughgp.io.readers` (profiles with rounded x accepted within their printed
digits), ``.x3p`` to :mod:`roughgp.io.x3p` (any writer), ``.npy`` is read here, and
binary or other instrument files go to SurfaceTopography
(:mod:`roughgp.io.instruments`). :class:`Measurement` holds ``z`` (``z[ix]`` or
``z[iy, ix]``, NaN where unmeasured), ``spacing`` in array order (µm), how the spacing and the
height unit were found, which reader read it, and what the file says besides.
:func:`mean_profile` reduces a surface to its mean profile (section 3.3 fits a profile).
"""

from __future__ import annotations

import dataclasses
import math
import re
import types
from pathlib import Path

import numpy as np

from roughgp.io import readers
from roughgp.io.instruments import UM_PER_UNIT, read_instrument
from roughgp.io.plausibility import BOUNDS, check_reading
from roughgp.io.readers import MalformedFileError
from roughgp.io.x3p import read_x3p

__all__ = ["Measurement", "READ_FORMATS", "TEXT_FORMATS", "read_measurement", "mean_profile"]

#: Extensions read by roughgp's own readers; ``.txt``, ``.csv``, ``.dat`` and ``.asc`` are
#: read as text when their content is text and by SurfaceTopography otherwise (MetroPro's
#: binary ``.dat``, say).
TEXT_FORMATS = (".csv", ".txt", ".dat", ".asc")
#: Formats read without SurfaceTopography; every other extension goes to it
#: (:func:`roughgp.io.instruments.instrument_formats` lists its readers).
READ_FORMATS = (".npy", ".xyz", ".x3p") + TEXT_FORMATS

_GIVEN = "as given (--spacing)"  # the spacing source when the caller gives the spacing
_UNIT_WORDS = {"um": "um", "µm": "um", "μm": "um", "micrometer": "um", "micrometre": "um",
               "micron": "um", "microns": "um", "micrometers": "um", "micrometres": "um",
               "mm": "mm", "millimeter": "mm", "millimetre": "mm", "nm": "nm",
               "nanometer": "nm", "nanometre": "nm", "m": "m", "meter": "m", "metre": "m"}


@dataclasses.dataclass
class Measurement:
    """Heights read from a file.

    Attributes:
        z: heights in µm, ``z[ix]`` (profile) or ``z[iy, ix]`` (surface), NaN where unmeasured.
        spacing: the steps in µm in array order, ``(dx,)`` or ``(dy, dx)``.
        spacing_source: where the spacing came from (the file, a column, ``--spacing``, or an
            assumption: then it says so).
        unit_source: the unit the file's heights were in and how it was found.
        reader: which reader read the file.
        meta: what the file says besides the heights (creator, instrument, offsets, ...).
        notes: what the reader did that the user should know (header lines skipped, ...).
    """

    z: np.ndarray
    spacing: tuple
    spacing_source: str
    unit_source: str = "um (assumed: the file states none)"
    reader: str = "roughgp"
    meta: types.MappingProxyType = dataclasses.field(
        default_factory=lambda: types.MappingProxyType({}))
    notes: tuple = ()

    @property
    def kind(self) -> str:
        """``"profile"`` (1-D) or ``"surface"`` (2-D)."""
        return "profile" if self.z.ndim == 1 else "surface"


def _check_input(path) -> Path:
    """The path, once it is known to be a readable, non-empty file (else what it is not)."""
    p = Path(path)
    if not p.exists():
        raise FileNotFoundError(2, "no such file", str(path))
    if not p.is_file():
        raise ValueError(f"not a file: {path}")
    try:
        with open(p, "rb") as stream:
            empty = stream.read(1) == b""
    except PermissionError:
        raise PermissionError(13, "permission denied: the file exists but cannot be read "
                                  "(check its permissions)", str(path)) from None
    if empty:
        raise MalformedFileError(f"{path}: the file is empty (0 bytes)")
    return p


def _is_text(path: Path) -> bool:
    """Whether the first 8 KiB look like text (UTF-16 with its mark; else no NUL byte and
    mostly printable)."""
    if readers.text_encoding(path) == "utf-16":
        return True
    with open(path, "rb") as stream:
        head = stream.read(8192)
    if b"\x00" in head:
        return False
    printable = sum(32 <= b < 127 or b in (9, 10, 13) or b >= 128 for b in head)
    return printable >= 0.95 * max(len(head), 1)


@dataclasses.dataclass
class _TextHeader:
    kind: str | None = None  # "profile" / "surface" from a roughgp CSV's comment
    spacing: float | None = None  # um, from a roughgp CSV's spacing_um comment
    units: tuple = ()  # per column, from the last header line (``x in µm,z in µm``)
    width: tuple | None = None  # (value, unit) from a Gwyddion "# Width:" line
    height: tuple | None = None  # (value, unit) from a Gwyddion "# Height:" line
    value_unit: str | None = None  # the heights' unit, from a "# Value units:" line
    first_column: str = ""  # the first column's name in the last header line


def _length(text: str):
    """``(value, unit)`` of ``"10.00 µm"``, or None."""
    m = re.match(r"^([-+]?[\d.]+(?:[eE][-+]?\d+)?)\s*([A-Za-zµμÅ]+)$", text.strip())
    if m is None or m.group(2) not in UM_PER_UNIT and m.group(2).lower() not in _UNIT_WORDS:
        return None
    try:
        return float(m.group(1)), m.group(2)
    except ValueError:
        return None


def _um_per(unit: str) -> float:
    return UM_PER_UNIT[unit] if unit in UM_PER_UNIT else UM_PER_UNIT[_UNIT_WORDS[unit.lower()]]


def _text_header(path: Path) -> _TextHeader:
    """What a text file says about itself before its data: a ``roughgp simulate`` CSV's kind
    and spacing, a Gwyddion matrix export's width, height and value unit (``# Width: 10.00
    µm``, ``# Value units: m``), and the units named in the last header line (one per column,
    e.g. ``Lateral um,Raw Micrometer``)."""
    found = _TextHeader()
    last_header = ""
    with open(path, encoding=readers.text_encoding(path), errors="replace") as stream:
        for _, line in zip(range(200), stream):
            text = line.strip()
            if re.match(r"^[-+.\d]", text) and re.search(r"\d", text):
                break
            m = re.match(r"#\s*roughgp (profile|surface)\b", text)
            found.kind = m.group(1) if m else found.kind
            m = re.match(r"#\s*spacing_um:\s*([^\s,;]+)", text)
            if m:
                try:
                    found.spacing = float(m.group(1))
                except ValueError:
                    pass
            m = re.match(r"#\s*(Width|Height|Value units):\s*(.+)$", text, re.IGNORECASE)
            if m and m.group(1).lower() == "value units":
                unit = m.group(2).strip()
                found.value_unit = unit if unit in UM_PER_UNIT or unit.lower() in _UNIT_WORDS \
                    else f"?{unit}"
            elif m:
                setattr(found, m.group(1).lower(), _length(m.group(2)) or ("?", m.group(2)))
            if text and not text.startswith("#"):
                last_header = text
    units = []
    columns = re.split(r"[,;\t]", last_header) if re.search(r"[,;\t]", last_header) \
        else last_header.split()  # ``µm µm``: one unit per whitespace-separated column
    for column in columns:
        words = [w for w in re.findall(r"[A-Za-zµμ]+", column.lower())]
        known = [_UNIT_WORDS[w] for w in words if w in _UNIT_WORDS]
        units.append(known[-1] if known else None)
    found.units = tuple(units)
    found.first_column = columns[0].strip().lower() if last_header else ""
    return found


def _bytes(n: int) -> str:
    """``n`` bytes in words: ``7.28 TiB``."""
    unit = max((k for k in range(7) if n >= 1024 ** k), default=0)
    return f"{n / 1024 ** unit:.3g} {('bytes', 'KiB', 'MiB', 'GiB', 'TiB', 'PiB', 'EiB')[unit]}"


def _npy(path: Path, kind: str, spacing):
    fmt = np.lib.format
    with open(path, "rb") as stream:
        if stream.read(6) != b"\x93NUMPY":
            raise MalformedFileError(f"{path}: not a .npy file (no NumPy header)")
        stream.seek(0)
        try:  # the header alone, before any allocation
            version = fmt.read_magic(stream)
            read = fmt.read_array_header_1_0 if version == (1, 0) else fmt.read_array_header_2_0
            shape, _, dtype = read(stream)
        except Exception as exc:  # truncated or malformed headers raise many kinds of errors
            raise MalformedFileError(f"{path}: not a readable .npy header "
                                     f"({type(exc).__name__}: {exc})") from None
        data_start = stream.tell()
    if dtype.hasobject:
        raise MalformedFileError(f"{path}: holds Python objects (a pickle), not numbers: "
                                 "refused (roughgp never unpickles a file)")
    if not (np.issubdtype(dtype, np.integer) or np.issubdtype(dtype, np.floating)):
        raise MalformedFileError(f"{path}: holds {dtype} values, not real heights"
                                 + (" (complex numbers: save the real part, z.real, or the "
                                    "modulus, abs(z), as you mean it)"
                                    if np.issubdtype(dtype, np.complexfloating) else ""))
    points = math.prod(shape)
    if points > readers.MAX_POINTS:
        raise MalformedFileError(f"{path}: declares an array of shape {shape} = {points:.3g} "
                                 f"points ({_bytes(points * dtype.itemsize)}), more "
                                 f"than MAX_POINTS = {readers.MAX_POINTS}")
    if path.stat().st_size - data_start < points * dtype.itemsize:
        raise MalformedFileError(f"{path}: truncated: the header declares {shape} of {dtype} "
                                 f"({points * dtype.itemsize} bytes), the file holds "
                                 f"{path.stat().st_size - data_start}")
    try:
        z = np.load(path, allow_pickle=False)
    except (ValueError, OSError, EOFError) as exc:
        raise MalformedFileError(f"{path}: not a readable .npy array ({exc})") from None
    if z.ndim == 2 and z.shape[0] == 1 and kind != "surface":
        z = z[0]
    if z.ndim not in (1, 2) or not np.issubdtype(z.dtype, np.number):
        raise MalformedFileError(f"{path}: expected a numeric profile (1-D) or surface (2-D), "
                                 f"got {z.dtype} of shape {z.shape}")
    z = np.asarray(z, dtype=np.float64)
    d = 1.0 if spacing is None else spacing
    source = _GIVEN if spacing is not None else "assumed: a .npy file stores none; give --spacing"
    return Measurement(z, (d,) * z.ndim, source, reader="numpy .npy")


def _height_map(hm, spacing, source, unit_source, reader):
    if spacing is not None:
        return Measurement(hm.z, (spacing,) * hm.z.ndim, _GIVEN + ", not the file's",
                           unit_source, reader, hm.meta)
    return Measurement(hm.z, tuple(hm.spacing), source, unit_source, reader, hm.meta)


def _is_xyz_list(table: np.ndarray) -> bool:
    """Whether a 3-column table is a list of x y z points: its first two columns take few
    distinct values, each (x, y) pair once, covering at least half of their grid."""
    if table.ndim != 2 or table.shape[1] != 3 or table.shape[0] < 4:
        return False
    xy = table[:, :2]
    if not np.all(np.isfinite(xy)):
        return False
    nx, ny = (np.unique(xy[:, k]).size for k in (0, 1))
    pairs = np.unique(xy, axis=0).shape[0]
    return nx >= 2 and ny >= 2 and pairs == table.shape[0] and nx * ny <= 2 * table.shape[0]


def _matrix_spacing(path, header: _TextHeader, shape) -> tuple[tuple, str] | None:
    """``((dy, dx), source)`` in µm from a Gwyddion matrix header's ``# Width:`` and
    ``# Height:`` (the field's extent: a step is the extent over the points), or None."""
    if header.width is None:
        return None
    extents = []
    for name, length in (("Height", header.height or header.width), ("Width", header.width)):
        value, unit = length
        if value == "?" or not (math.isfinite(value) and value > 0):
            raise MalformedFileError(f"{path}: the header's '# {name}:' line does not give a "
                                     f"length roughgp reads ({unit!r}); a number and a unit "
                                     "such as '10.00 µm'")
        extents.append(value * _um_per(unit))
    return ((extents[0] / shape[0], extents[1] / shape[1]),
            "from the header's '# Width:'" + (" and '# Height:'" if header.height else "")
            + " over the points")


def _index_column(header: _TextHeader, table: np.ndarray) -> bool:
    """Whether the first of 3 columns is a point index (headed ``index``, ``#``, ``n`` or
    ``no``; 0, 1, 2, ... or 1, 2, 3, ...) before x and z."""
    if table.shape[1] != 3 or header.first_column not in ("index", "#", "n", "no", "point"):
        return False
    first = table[:, 0]
    return bool(np.all(first == np.arange(first.size) + first[0]) and first[0] in (0, 1))


def _text(path: Path, kind: str, spacing, unit) -> Measurement:
    header = _text_header(path)
    table, _, skipped = readers.read_surface(path, spacing=1.0, return_header=True)
    notes = tuple(f"header line {n} skipped: {text[:60]!r}" for n, text in skipped)
    units = header.units
    indexed = _index_column(header, table)
    if indexed:
        table, units = table[:, 1:], units[1:]
        notes += ("the first column, a point index, left out",)
    columns = table.shape[1]
    if header.kind is None and kind != "profile" and _is_xyz_list(table):
        z, (dy, dx) = readers.read_xyz(path)
        notes += (f"read as x y z points (3 columns whose x and y lie on a {z.shape[0]} x "
                  f"{z.shape[1]} grid)",)
        z, unit_source = _given_unit(z, unit)
        if spacing is not None:
            return Measurement(z, (spacing, spacing), _GIVEN + ", not the file's", unit_source,
                               reader="roughgp xyz (by content)", notes=notes)
        return Measurement(z, (dy, dx), "from the x y positions", unit_source,
                           reader="roughgp xyz (by content)", notes=notes)
    if kind == "surface" and columns <= 2 and header.kind is None and header.width is None \
            and header.value_unit is None:  # no surface is 1 or 2 points wide
        kind = "profile"
        notes += (("2 columns (x and z)" if columns == 2 else "1 column (heights)")
                  + f": read as a profile, not as a surface {columns} wide",)
    if kind == "profile" and columns > 2:
        raise MalformedFileError(f"{path}: has {columns} columns; a profile is 1 column "
                                 "(heights) or 2 (x, z): read it as a surface (kind "
                                 "'surface' or 'auto')")
    if kind == "auto" and header.kind is None and columns == 3 and header.width is None:
        raise MalformedFileError(f"{path}: 3 columns that are neither a profile nor x y z points "
                                 "on a grid (the x and y columns do not form a grid): ambiguous; "
                                 "read it as a height grid 3 points wide with kind 'surface' "
                                 "(--kind surface)")
    if kind == "auto":
        matrix = header.width is not None or header.value_unit is not None
        kind = header.kind or ("surface" if matrix or columns > 2 else "profile")
    if header.value_unit is not None and header.value_unit.startswith("?"):
        raise MalformedFileError(f"{path}: the header's '# Value units:' line names "
                                 f"{header.value_unit[1:]!r}, not a length unit roughgp knows "
                                 f"({', '.join(UM_PER_UNIT)})")
    if spacing is not None:
        step, source = (spacing, spacing), _GIVEN
    elif header.spacing is not None:
        step, source = (header.spacing,) * 2, "from the file's spacing_um comment"
    else:
        step, source = (1.0, 1.0), "assumed: the file states none; give --spacing"
    if kind == "surface":
        z = table
        matrix = None if spacing is not None else _matrix_spacing(path, header, z.shape)
        if matrix is not None:
            step, source = matrix
        if header.value_unit is not None and unit is None:
            z = z * _um_per(header.value_unit)
            unit_source = f"{header.value_unit} (from the header's '# Value units:')"
        else:
            z, unit_source = _given_unit(z, unit)
        return Measurement(z, step, source, unit_source, reader="roughgp text grid",
                           notes=notes)
    if columns == 1:  # heights only
        _, z = readers.read_profile(path, spacing=step[0])
        z, unit_source = _given_unit(z, unit)
        return Measurement(z, step[:1], source, unit_source, reader="roughgp text profile",
                           notes=notes)
    x_unit = units[0] if units else None
    z_unit = units[1] if len(units) > 1 else None
    if unit is not None:
        z_unit = None  # the heights' unit as given replaces the column header's
    scales = (UM_PER_UNIT[x_unit] if x_unit else 1.0, UM_PER_UNIT[z_unit] if z_unit else 1.0)
    columns_used = {"x_column": 1, "z_column": 2} if indexed else {}
    x, z, digits = readers.read_profile(path, unit_scale=scales, return_digits=True,
                                        **columns_used)
    if z_unit:
        unit_source = f"{z_unit} (from the column header)"
    else:
        z, unit_source = _given_unit(z, unit)
    if spacing is None:
        step, residual = readers.profile_step(x, digits, path=path)
        source = "from the x column" + (f" ({x_unit}, from the column header)" if x_unit
                                        else " (its unit assumed um)")
        if residual > 1e-6 * step:
            source += (f": x printed rounded, on the grid within {residual:.3g} um (the "
                       "printed digits' rounding)")
        step = (step,)
    return Measurement(z, step[:1], source, unit_source, "roughgp text profile", notes=notes)


def _given_unit(z, unit):
    """Heights from a file that states no unit: in ``unit`` when given (converted to µm),
    else assumed µm; and the unit's source in words."""
    if unit is None:
        return z, "um (assumed: the file states none)"
    return z * UM_PER_UNIT[unit], f"{unit} (as given)" + (", converted to um"
                                                          if UM_PER_UNIT[unit] != 1 else "")


def read_measurement(path, *, kind: str = "auto", spacing: float | None = None,
                     channel: int = 0, unit: str | None = None) -> Measurement:
    """Read a profile or a surface (heights in µm) from a file of any format read.

    Every reading is checked for plausibility
    (:func:`roughgp.io.plausibility.check_reading`: heights within a metre, steps from
    1 pm to 1 m, a field within a metre, at least one measured point).

    Args:
        path: the file.
        kind: ``"auto"``, or ``"profile"`` / ``"surface"`` for a text table (a table of 1 or
            2 columns whose header states no grid is a profile whatever ``kind`` says).
        spacing: µm, overriding the file's (x3p, instruments, xyz, a profile's x column, the
            comment of a ``roughgp simulate`` CSV, a Gwyddion matrix header); without either
            it is 1 µm (and says so).
        channel: the data channel of an instrument file (AFM files hold several).
        unit: the length unit of the heights (one of
            :data:`~roughgp.io.instruments.UM_PER_UNIT`): for an instrument or text
            file it replaces the unit the file states (or the µm assumed where it states
            none), for ``.npy`` it is the heights' unit; an ``.x3p`` file always stores
            metres and refuses it.

    Raises:
        FileNotFoundError: no such file.
        PermissionError: the file cannot be read (its permissions).
        MalformedFileError: a file that cannot be read as what it is, or whose reading is
            implausible (the message names the file and the problem).
        ValueError: a bad argument (named).
    """
    path = _check_input(path)
    if kind not in ("auto", "profile", "surface"):
        raise ValueError(f"kind must be 'auto', 'profile' or 'surface', got {kind!r}")
    low, high = BOUNDS["step"]
    if spacing is not None and not (math.isfinite(spacing) and low <= spacing <= high):
        raise ValueError(f"spacing must be from {low:g} to {high:g} um (1 pm to 1 m), got "
                         f"{spacing!r}")
    if unit is not None and unit not in UM_PER_UNIT:
        raise ValueError(f"unit must be one of {', '.join(UM_PER_UNIT)}, got {unit!r}")
    measurement = _read(path, kind, spacing, channel, unit)
    check_reading(measurement.z, measurement.spacing, path)
    return measurement


def _read(path: Path, kind: str, spacing, channel, unit) -> Measurement:
    ext = path.suffix.lower()
    if ext == ".npy":
        m = _npy(path, kind, spacing)
        z, unit_source = _given_unit(m.z, unit)
        return dataclasses.replace(m, z=z, unit_source=unit_source)
    if ext == ".x3p":
        if unit is not None:
            raise ValueError(f"unit: an .x3p file stores metres, so a unit ({unit!r}) does not "
                             f"apply to {path}")
        hm = read_x3p(path)
        return _height_map(hm, spacing, "from the x3p file", "m (x3p stores metres), converted to um",
                           "roughgp x3p" + (f", {hm.meta['reader']}" if "reader" in hm.meta
                                            else " (x3pio)"))
    if ext == ".xyz":
        z, (dy, dx) = readers.read_xyz(path)
        z, unit_source = _given_unit(z, unit)
        if spacing is not None:
            return Measurement(z, (spacing, spacing), _GIVEN + ", not the file's", unit_source,
                               reader="roughgp xyz")
        return Measurement(z, (dy, dx), "from the x y positions", unit_source,
                           reader="roughgp xyz")
    if ext in TEXT_FORMATS and _is_text(path):
        return _text(path, kind, spacing, unit)
    try:
        hm = read_instrument(path, channel=channel, unit=unit)
    except MalformedFileError as error:
        if "no reader recognises" not in str(error):
            raise
        raise MalformedFileError(f"{path}: not a format roughgp reads ({', '.join(READ_FORMATS)}"
                                 ") nor one that SurfaceTopography recognises by its content "
                                 "(instrument formats: roughgp texture --help lists them)") \
            from None
    unit_source = hm.meta["unit"]
    if UM_PER_UNIT.get(unit_source.split(" ")[0]) != 1.0:  # not um, µm or μm
        unit_source += ", converted to um"
    return _height_map(hm, spacing, "from the file", unit_source, hm.meta["reader"])


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

