"""Readers and writers for a user's own measurements: text / CSV profiles and height grids,
x-y-z point files on a regular grid, and ISO 25178-72 ``.x3p`` files (through ``x3pio``).

Layout and units (the library's convention, :mod:`roughgp.common.grid`): a profile is ``z[ix]``, a
surface ``z[iy, ix]`` (rows are y, y grows with the row index); ``spacing`` is in array order,
``(dy, dx)``. Text readers return values in the file's units times ``unit_scale``; x3p files
are read and written in micrometres (the file itself stores metres). ``NaN`` marks a point
that was not measured; it is allowed in heights, never in positions or spacings.

Text files: blank lines and lines starting with ``#``, ``%`` or ``//`` are skipped anywhere;
with ``skiprows="auto"`` the non-numeric lines before the first numeric one (a header) are
skipped too, and a non-numeric line after it is an error. ``delimiter=None`` splits on commas,
semicolons, tabs and spaces (one trailing delimiter on a line is ignored); decimal commas are
not supported. A height written as ``nan``, ``NA`` or an empty field (explicit delimiter) is a
missing point.

Every problem with a file raises :class:`MalformedFileError` (a ``ValueError``) whose message
starts with the file name (and the line, for text files) and says what is wrong; a bad
argument raises a plain ``ValueError`` that names the parameter. Sizes are checked before
any large allocation: a grid of more than :data:`MAX_POINTS` points is refused.
"""

from __future__ import annotations

import dataclasses
import math
import os
import re
import types
import zipfile
import zlib

import numpy as np

from roughgp.common.checks import check_positive
from roughgp.common.grid import normalize

__all__ = ["MAX_POINTS", "MAX_XML_BYTES", "MalformedFileError", "HeightMap", "read_profile",
           "read_surface", "read_xyz", "read_x3p", "write_x3p"]

#: Largest number of grid points a reader allocates (2**28 = 268 million: 2 GiB of float64).
MAX_POINTS = 2 ** 28
#: Largest uncompressed ``main.xml`` of an x3p file that is parsed (256 MiB).
MAX_XML_BYTES = 2 ** 28

_UM_PER_M = 1e6
_COMMENT = ("#", "%", "//")
_AUTO_SPLIT = re.compile(r"\s*[,;\t]\s*|\s+")
_MISSING = frozenset({"", "nan", "-nan", "+nan", "na", "n/a"})


class MalformedFileError(ValueError):
    """A file that cannot be read as asked: the message names the file and the problem."""


def _name(path) -> str:
    return os.fspath(path) if isinstance(path, (str, os.PathLike)) else repr(path)


def _bad(path, problem: str, line: int | None = None) -> MalformedFileError:
    where = f"{_name(path)}: line {line}" if line is not None else _name(path)
    return MalformedFileError(f"{where}: {problem}")


# --------------------------------------------------------------------------- text tables

def _token(text: str) -> float:
    try:
        return float(text)
    except ValueError:
        if text.strip().lower() in _MISSING:
            return math.nan
        raise


def _read_table(path, *, delimiter=None, skiprows="auto"):
    """Parse a numeric text table: returns ``(values, lines)``, the values as a float64 array
    of shape (rows, columns) and the 1-based line number of each row."""
    if skiprows != "auto" and not (isinstance(skiprows, (int, np.integer))
                                   and not isinstance(skiprows, bool) and skiprows >= 0):
        raise ValueError(f"skiprows must be 'auto' or an integer >= 0, got {skiprows!r}")
    if delimiter is not None and (not isinstance(delimiter, str) or delimiter == ""):
        raise ValueError(f"delimiter must be None (commas, semicolons, tabs or spaces) or a "
                         f"non-empty string such as ',' or '\\t', got {delimiter!r}")

    def split(line):
        if delimiter is None:
            line = line.rstrip(",;")
            return _AUTO_SPLIT.split(line.strip()) if line.strip() else []
        return [t.strip() for t in line.split(delimiter)]

    flat: list[float] = []
    lines: list[int] = []
    width = None
    with open(path, encoding="utf-8-sig", errors="replace", newline=None) as stream:
        for number, raw in enumerate(stream, start=1):
            if skiprows != "auto" and number <= skiprows:
                continue
            line = raw.strip()
            if not line or line.startswith(_COMMENT):
                continue
            tokens = split(raw.rstrip("\r\n"))
            try:
                row = [_token(t) for t in tokens]
            except ValueError:
                if skiprows == "auto" and not lines:
                    continue  # a header line before the first numeric line
                shown = line if len(line) <= 60 else line[:57] + "..."
                raise _bad(path, f"not a row of numbers: {shown!r} (header lines are only "
                                 "allowed before the data; see skiprows, delimiter)",
                           number) from None
            if width is None:
                width = len(row)
            elif len(row) != width:
                raise _bad(path, f"{len(row)} values, but the first data row (line "
                                 f"{lines[0]}) has {width}", number)
            flat.extend(row)
            lines.append(number)
    if not lines:
        raise _bad(path, "no rows of numbers found")
    return np.array(flat, dtype=np.float64).reshape(len(lines), width), lines


def _check_column(path, name, column, width):
    if not (isinstance(column, (int, np.integer)) and not isinstance(column, bool)):
        raise ValueError(f"{name} must be an integer column index, got {column!r}")
    if not -width <= column < width:
        raise _bad(path, f"{name}={column} is out of range: the file has {width} "
                         f"column{'s' if width != 1 else ''}")


def _check_heights(path, z, lines, what="height"):
    """Heights may be NaN (missing), never infinite."""
    bad = np.isinf(z)
    if np.any(bad):
        row = int(np.argwhere(bad)[0][0])
        raise _bad(path, f"infinite {what} (NaN marks a missing point)", lines[row])


def _scale(name, value):
    value = float(value) if np.ndim(value) == 0 else value
    check_positive(name, value)
    return value


def read_profile(path, *, x_column=0, z_column=None, spacing=None, delimiter=None,
                 skiprows="auto", unit_scale=1.0):
    """Read a profile from a text / CSV file: columns (x, z), or heights only.

    Args:
        path: the file.
        x_column, z_column: 0-based column indices (negative counts from the end). Without
            ``spacing``, x comes from ``x_column`` and z from ``z_column`` (default 1).
        spacing: > 0; when given, the file holds heights only: z is column ``z_column``
            (default 0), ``x = ix * spacing`` (in the output unit, not scaled), and
            ``x_column`` is not used.
        delimiter, skiprows: see the module docstring.
        unit_scale: > 0, a factor applied to the values read (e.g. 1000 for millimetres to
            micrometres); a pair ``(x_scale, z_scale)`` scales x and z differently.

    Returns:
        ``(x, z)``: float64 arrays of shape (n,), ``n >= 2``. x is finite and strictly
        increasing (not necessarily uniform); z may hold NaN for missing points.

    Raises:
        MalformedFileError: naming the file and line: non-numeric data, ragged rows, a
            missing column, NaN or non-increasing x, infinite z, fewer than 2 points.
        ValueError: a bad parameter (named).
    """
    scales = np.broadcast_to(np.asarray(unit_scale, dtype=np.float64), (2,))
    check_positive("unit_scale", scales)
    if spacing is not None:
        spacing = _scale("spacing", spacing)
        if np.ndim(spacing) != 0:
            raise ValueError(f"spacing must be a scalar for a profile, got {spacing!r}")
    values, lines = _read_table(path, delimiter=delimiter, skiprows=skiprows)
    width = values.shape[1]
    if z_column is None:
        z_column = 0 if spacing is not None else 1
    _check_column(path, "z_column", z_column, width)
    z = values[:, z_column] * scales[1]
    _check_heights(path, z, lines)
    if len(z) < 2:
        raise _bad(path, f"a profile needs at least 2 points, found {len(z)}")
    if spacing is not None:
        return np.arange(len(z)) * float(spacing), np.ascontiguousarray(z)

    _check_column(path, "x_column", x_column, width)
    x = values[:, x_column] * scales[0]
    bad = ~np.isfinite(x)
    if np.any(bad):
        raise _bad(path, "x (column x_column) must be finite: missing or infinite positions "
                         "are not allowed (NaN is only allowed in heights)",
                   lines[int(np.argmax(bad))])
    steps = np.diff(x)
    if np.any(steps <= 0):
        i = int(np.argmax(steps <= 0)) + 1
        raise _bad(path, f"x must be strictly increasing, but x = {x[i]!r} follows "
                         f"x = {x[i - 1]!r} (column x_column={x_column}; sort the file or "
                         "check the column)", lines[i])
    return np.ascontiguousarray(x), np.ascontiguousarray(z)


def read_surface(path, *, spacing, delimiter=None, skiprows="auto", unit_scale=1.0):
    """Read a grid of heights from a text / CSV file: row ``iy`` of the data holds
    ``z[iy, 0], z[iy, 1], ...`` (rows are y, columns x).

    Args:
        path: the file.
        spacing: scalar or ``(dy, dx)`` in array order, > 0, in the output unit.
        delimiter, skiprows: see the module docstring.
        unit_scale: > 0, a factor applied to the heights read.

    Returns:
        ``(z, spacing)``: ``z[iy, ix]`` float64 of shape (ny, nx) (NaN: missing points)
        and ``spacing`` as a tuple ``(dy, dx)`` of floats.

    Raises:
        MalformedFileError: naming the file and line: non-numeric data, rows of different
            lengths, infinite heights, more than :data:`MAX_POINTS` points.
        ValueError: a bad parameter (named).
    """
    unit_scale = _scale("unit_scale", unit_scale)
    _, spacing = normalize((1, 1), spacing)
    z, lines = _read_table(path, delimiter=delimiter, skiprows=skiprows)
    if z.size > MAX_POINTS:
        raise _bad(path, f"{z.shape[0]} x {z.shape[1]} points exceed MAX_POINTS = {MAX_POINTS}")
    z *= unit_scale
    _check_heights(path, z, lines)
    return z, (float(spacing[0]), float(spacing[1]))


def _grid_axis(path, name, values, lines):
    """Indices of ``values`` on a regular grid and its spacing, or an error."""
    unique = np.unique(values)
    if unique.size < 2:
        raise _bad(path, f"all points have the same {name} = {unique[0]!r}: not a surface "
                         "(read a profile with read_profile)")
    gaps = np.diff(unique)
    k = int(np.argmin(gaps))
    smallest = float(gaps[k])
    span = (float(unique[-1]) - float(unique[0])) / smallest
    if not span < MAX_POINTS:
        raise _bad(path, f"the {name} values span {span:.3g} times their smallest step "
                         f"{smallest!r}: the grid would exceed MAX_POINTS = {MAX_POINTS}")
    steps = np.rint((unique - unique[0]) / smallest)
    step = float(np.dot(steps, unique - unique[0]) / np.dot(steps, steps))  # least squares
    residual = np.abs(unique - unique[0] - steps * step)
    if residual.max() > 0.01 * step:
        # the smallest gap sets the step, so its upper end is the likeliest stray value
        raise _bad(path, f"the {name} values are not on a regular grid: the gaps between "
                         f"distinct values ({gaps.min():.6g} to {gaps.max():.6g}) are not "
                         f"whole multiples of one step (to 1%); smallest gap between "
                         f"{name} = {float(unique[k])!r} and {float(unique[k + 1])!r}",
                   lines[int(np.argmax(values == unique[k + 1]))])
    index = np.rint((values - unique[0]) / step).astype(np.int64)
    return index, int(steps[-1]) + 1, step


def read_xyz(path, *, columns=(0, 1, 2), delimiter=None, skiprows="auto", unit_scale=1.0):
    """Read points (x, y, z), one per line in any order, that lie on a regular grid.

    The grid starts at the smallest x and y; its steps are fitted to the distinct x (and y)
    values, which must be integer multiples of one step to within 1% of it. Grid points
    that the file does not list are NaN, as are points whose height is NaN.

    Args:
        path: the file.
        columns: the 0-based column indices of x, y and z.
        delimiter, skiprows: see the module docstring.
        unit_scale: > 0, applied to every value; a pair ``(lateral, height)`` scales
            x, y and z differently.

    Returns:
        ``(z, spacing)``: ``z[iy, ix]`` float64 of shape (ny, nx), rows in increasing y,
        and ``spacing = (dy, dx)`` as floats.

    Raises:
        MalformedFileError: naming the file (and line): NaN / infinite positions, infinite
            heights, positions off a regular grid, a grid point listed twice, a grid of
            more than :data:`MAX_POINTS` points (refused before it is allocated).
        ValueError: a bad parameter (named).
    """
    scales = np.broadcast_to(np.asarray(unit_scale, dtype=np.float64), (2,))
    check_positive("unit_scale", scales)
    if len(columns) != 3:
        raise ValueError(f"columns must be three column indices (x, y, z), got {columns!r}")
    values, lines = _read_table(path, delimiter=delimiter, skiprows=skiprows)
    for name, column in zip(("columns[0] (x)", "columns[1] (y)", "columns[2] (z)"), columns):
        _check_column(path, name, column, values.shape[1])
    x, y = values[:, columns[0]] * scales[0], values[:, columns[1]] * scales[0]
    z = values[:, columns[2]] * scales[1]
    for name, v in (("x", x), ("y", y)):
        bad = ~np.isfinite(v)
        if np.any(bad):
            raise _bad(path, f"{name} must be finite (NaN is only allowed in heights)",
                       lines[int(np.argmax(bad))])
    _check_heights(path, z, lines)
    ix, nx, dx = _grid_axis(path, "x", x, lines)
    iy, ny, dy = _grid_axis(path, "y", y, lines)
    if nx * ny > MAX_POINTS:
        raise _bad(path, f"the grid of {ny} x {nx} points exceeds MAX_POINTS = {MAX_POINTS}")
    flat = iy * nx + ix
    order = np.argsort(flat, kind="stable")
    repeated = np.nonzero(np.diff(flat[order]) == 0)[0]
    if repeated.size:
        first, second = sorted((order[repeated[0]], order[repeated[0] + 1]))
        raise _bad(path, f"the grid point (x, y) = ({x[second]!r}, {y[second]!r}) is listed "
                         f"twice (also on line {lines[first]})", lines[second])
    grid = np.full(ny * nx, np.nan)
    grid[flat] = z
    return grid.reshape(ny, nx), (dy, dx)


# --------------------------------------------------------------------------- x3p

@dataclasses.dataclass(frozen=True)
class HeightMap:
    """Heights read from an x3p file.

    Attributes:
        z: float64 heights in micrometres, ``z[ix]`` (profile) or ``z[iy, ix]`` (surface,
            rows are y, y growing with the row index); NaN marks points not measured.
        spacing: the grid steps in micrometres in array order: ``(dx,)`` or ``(dy, dx)``.
        unit: ``"um"`` (micrometres), the unit of ``z`` and ``spacing``.
        meta: read-only mapping with what the file says besides the heights:
            ``feature_type``, ``revision``, ``layer_count``, ``offset`` (x, y, z of the
            first point, micrometres), ``creator``, ``date``, ``instrument``,
            ``probing_system``, ``comment`` (``None`` where the file has none).
    """

    z: np.ndarray
    spacing: tuple[float, ...]
    unit: str = "um"
    meta: types.MappingProxyType = dataclasses.field(
        default_factory=lambda: types.MappingProxyType({}))


def _x3pio():
    import x3pio  # imported here: only the x3p functions need it
    return x3pio


def _check_container(path):
    """The zip-level checks x3pio leaves to its caller: main.xml's declared size."""
    try:
        with zipfile.ZipFile(path) as archive:
            infos = [i for i in archive.infolist() if not i.is_dir()]
    except zipfile.BadZipFile as error:
        raise _bad(path, f"not an x3p file: not a (valid) zip archive ({error})") from None
    mains = [i for i in infos if i.filename.replace("\\", "/").split("/")[-1] == "main.xml"]
    if not mains:
        raise _bad(path, "not an x3p file: the zip archive holds no main.xml")
    for info in mains:
        if info.file_size > MAX_XML_BYTES:
            raise _bad(path, f"{info.filename} declares {info.file_size} bytes, more than "
                             f"MAX_XML_BYTES = {MAX_XML_BYTES}")


def _text(value):
    return None if value is None else str(value)


def read_x3p(path, *, layer=0) -> HeightMap:
    """Read a profile or a surface from an ISO 25178-72 ``.x3p`` file, in micrometres.

    x3p stores lengths and heights in metres; they are multiplied by 1e6 here. x3pio gives
    a surface layer as ``(rows, columns) = (SizeY, SizeX)`` with y growing with the row
    (the data file runs x fastest), which is already ``z[iy, ix]``: no transpose is needed.
    An axis with a negative increment is flipped so that positions grow with the index.
    The MD5 checksums of ``main.xml`` and of the binary data are verified by x3pio (a
    missing checksum is accepted, as x3pio does); XML is parsed by defusedxml (entity
    expansion refused).

    Args:
        path: the file.
        layer: which layer of a multi-layer file (0-based).

    Returns:
        A :class:`HeightMap`.

    Raises:
        MalformedFileError: naming the file: not a zip / damaged zip, no main.xml, wrong
            checksum, XML entities or other invalid XML, more than :data:`MAX_POINTS` points
            (refused before the data are read), data of another size than declared,
            non-finite or zero spacing, a point cloud or an irregular (absolute) x / y axis.
        FileNotFoundError / OSError: the file cannot be opened.
    """
    x3pio = _x3pio()
    expected = (x3pio.X3pError, zipfile.BadZipFile, zlib.error, EOFError,
                NotImplementedError, UnicodeDecodeError)
    _check_container(path)
    try:
        info = x3pio.info(path)
    except expected as error:
        raise _bad(path, f"not a valid x3p file: {error}") from None
    header = info.header
    kind = info.feature_type.name
    if kind not in ("PROFILE", "SURFACE"):
        raise _bad(path, f"holds a {kind.lower().replace('_', ' ')}, not a profile or a "
                         "surface on a regular grid")
    axes = (("y", header.y), ("x", header.x)) if kind == "SURFACE" else (("x", header.x),)
    for name, axis in axes:
        if not axis.is_incremental:
            raise _bad(path, f"the {name} axis is absolute (irregular positions): only "
                             "regular grids are read")
        if not (math.isfinite(axis.increment) and axis.increment != 0):
            raise _bad(path, f"the {name} increment {axis.increment!r} is not finite and "
                             "non-zero")
    points = math.prod(info.shape) * info.layer_count
    if points > MAX_POINTS:
        shape = " x ".join(str(n) for n in info.shape)
        raise _bad(path, f"declares {info.layer_count} layer(s) of {shape} = {points} points, "
                         f"more than MAX_POINTS = {MAX_POINTS}")
    if not (isinstance(layer, (int, np.integer)) and 0 <= layer < info.layer_count):
        raise ValueError(f"layer must be an integer in [0, {info.layer_count}) for "
                         f"{_name(path)}, got {layer!r}")

    try:
        file = x3pio.read(path)
    except expected as error:
        raise _bad(path, f"not a valid x3p file: {error}") from None
    z = np.array(file.layers[layer].z, dtype=np.float64) * _UM_PER_M
    z[np.isinf(z)] = np.nan  # x3pio already reads inf as "not measured"; be sure
    if z.ndim != len(axes):
        raise _bad(path, f"layer {layer} has shape {z.shape}, expected {len(axes)}-D")
    spacing = []
    for ax, (name, axis) in enumerate(axes):
        if axis.increment < 0:
            z = np.flip(z, axis=ax)
        spacing.append(abs(float(axis.increment)) * _UM_PER_M)

    metadata = info.metadata
    instrument = getattr(metadata, "instrument", None)
    probing = getattr(metadata, "probing_system", None)
    meta = {
        "feature_type": kind.lower(),
        "revision": _text(getattr(info.revision, "value", info.revision)),
        "layer_count": info.layer_count,
        "offset": tuple(float(v) * _UM_PER_M for v in info.placement.offset),
        "creator": _text(getattr(metadata, "creator", None)),
        "date": getattr(metadata, "date", None),
        "instrument": None if instrument is None else " ".join(
            str(v) for v in (instrument.manufacturer, instrument.model, instrument.serial,
                             instrument.version) if v),
        "probing_system": None if probing is None else " ".join(
            str(getattr(v, "name", v)) for v in (probing.type, probing.identification) if v),
        "comment": _text(getattr(metadata, "comment", None)),
    }
    return HeightMap(np.ascontiguousarray(z), tuple(spacing), "um",
                     types.MappingProxyType(meta))


def write_x3p(path, z, spacing, *, comment=None) -> None:
    """Write a profile ``z[ix]`` or a surface ``z[iy, ix]`` to an ISO 25178-72 ``.x3p`` file.

    The layout is that of :func:`read_x3p`: heights and ``spacing`` (scalar or array order,
    ``(dy, dx)``) in micrometres; they are stored in metres (times 1e-6) as float64 with
    x3pio's documented ``x3pio.write``, so ``read_x3p`` gives them back to float rounding.
    NaN marks a missing point; infinite heights are refused. ``Record2`` names roughgp as
    the software (x3p's record of data not measured), with ``comment`` if given.

    Raises:
        ValueError: ``z`` not 1-D / 2-D or holding infinite values, or a bad ``spacing``.
    """
    x3pio = _x3pio()
    arr = np.asarray(z, dtype=np.float64)
    if arr.ndim not in (1, 2) or arr.size == 0:
        raise ValueError(f"z must be a non-empty profile z[ix] or surface z[iy, ix], "
                         f"got shape {arr.shape}")
    if np.any(np.isinf(arr)):
        raise ValueError("z must not hold infinite values (NaN marks a missing point)")
    _, spacing = normalize(arr.shape, spacing)
    from roughgp import __version__
    metadata = x3pio.Metadata.for_software("roughgp", __version__)
    metadata.comment = None if comment is None else str(comment)
    options = {"metadata": metadata}
    heights = arr / _UM_PER_M
    if arr.ndim == 1:
        x3pio.write(path, heights, x_scale=float(spacing[0]) / _UM_PER_M, **options)
    else:
        x3pio.write(path, heights, x_scale=float(spacing[1]) / _UM_PER_M,
                    y_scale=float(spacing[0]) / _UM_PER_M, **options)
