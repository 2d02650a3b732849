"""Readers for a user's own measurements in text: CSV / text profiles and height grids, and
x-y-z point files on a regular grid (``.x3p``: :mod:`roughgp.io.x3p`; instrument
formats: :mod:`roughgp.io.instruments`).

Layout and units (the library's convention, :mod:`roughgp.common.grid`): a profile is ``z[ix]``, a
surface ``z[iy, ix]`` (rows are y, y grows with the row index); ``spacing`` is in array order,
``(dy, dx)``. Text readers return values in the file's units times ``unit_scale``. ``NaN`` marks a point
that was not measured; it is allowed in heights, never in positions or spacings.

Text files are UTF-8 (or ASCII), or UTF-16 with its byte-order mark. Blank lines and lines
starting with ``#``, ``%`` or ``//`` are skipped anywhere; with ``skiprows="auto"`` the
non-numeric lines before the first numeric one (a header) are skipped too (and a count line,
one whole number right before rows of several values), and a non-numeric line after it is an
error. ``delimiter=None`` splits on commas,
semicolons, tabs and spaces (one trailing delimiter on a line is ignored), except in a file whose
first line (header or data) holds a semicolon: then ``;`` is the delimiter and a comma in a
number is its decimal comma (``0,5;1,25``: the European CSV), never a column break. A line is a
header only when it holds a word (``x_um,z_um``, ``Profile 1``); a line of malformed numbers
(``0,1.2.5``) or with a NUL byte is an error, not a header. A height written as ``nan``, ``NA`` or an empty field (explicit delimiter) is a
missing point. Printed x positions are rounded: :func:`profile_step` accepts a grid whose
residuals stay within the rounding of the printed digits.

Every problem with a file raises :class:`MalformedFileError` (a ``ValueError``) whose message
starts with the file name (and the line, for text files) and says what is wrong; a bad
argument raises a plain ``ValueError`` that names the parameter. Sizes are checked before
any large allocation: a grid of more than :data:`MAX_POINTS` points is refused, and a text
file larger than :data:`MAX_TEXT_BYTES` is refused before it is parsed (values are stored
as float64 while parsing, and parsing stops at :data:`MAX_POINTS` values).
"""

from __future__ import annotations

import math
import os
import re
from array import array

import numpy as np

from roughgp.common.checks import check_positive
from roughgp.common.grid import normalize

__all__ = ["MAX_POINTS", "MAX_TEXT_BYTES", "MalformedFileError", "text_encoding", "read_profile",
           "read_surface", "read_xyz", "profile_step", "ROUNDING_TOLERANCE"]

#: Largest number of grid points a reader allocates (2**28 = 268 million: 2 GiB of float64).
MAX_POINTS = 2 ** 28
#: Largest text table read (256 MiB), checked before parsing: save larger maps as .npy or .x3p.
MAX_TEXT_BYTES = 2 ** 28

_UM_PER_M = 1e6
_COMMENT = ("#", "%", "//")
_AUTO_SPLIT = re.compile(r"\s*[,;\t]\s*|\s+")
_MISSING = frozenset({"", "nan", "-nan", "+nan", "na", "n/a"})
_DECIMAL = re.compile(r"^[+-]?(\d*)(?:\.(\d*))?(?:[eE]([+-]?\d+))?$")
#: A printed x is on the grid when its residual is within this many units of its last digit
#: (0.5: rounding to the printed digits; the rest: the least-squares line's own error).
ROUNDING_TOLERANCE = 0.51


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


def _last_digit_unit(token: str) -> float:
    """The unit of the last printed digit of a number (``"1.25"`` -> 0.01, ``"3e-4"`` ->
    1e-4); NaN where the token is not a plain decimal number."""
    m = _DECIMAL.match(token.strip())
    if m is None:
        return math.nan
    return 10.0 ** (int(m.group(3) or 0) - len(m.group(2) or ""))


_WORD = re.compile(r"[A-Za-z_\u00b5\u03bc]")


def _is_header(tokens) -> bool:
    """A header line holds a word: a token with a letter that is no number, nor a missing mark."""
    for token in tokens:
        try:
            _token(token)
        except ValueError:
            if _WORD.search(token):
                return True
    return False


def _read_table(path, *, delimiter=None, skiprows="auto", units_of=None, header=None):
    """Parse a numeric text table: returns ``(values, lines)``, the values as a float64 array
    of shape (rows, columns) and the 1-based line number of each row; with ``units_of`` (a
    column index) also the unit of the last printed digit of that column, per row. ``header``:
    a list that receives ``(line number, text)`` of each header line skipped."""
    if skiprows != "auto" and not (isinstance(skiprows, (int, np.integer))
                                   and not isinstance(skiprows, bool) and skiprows >= 0):
        raise ValueError(f"skiprows must be 'auto' or an integer >= 0, got {skiprows!r}")
    if delimiter is not None and (not isinstance(delimiter, str) or delimiter == ""):
        raise ValueError(f"delimiter must be None (commas, semicolons, tabs or spaces) or a "
                         f"non-empty string such as ',' or '\\t', got {delimiter!r}")

    semicolons = None  # decided on the first line: ";" separators with decimal commas

    def split(line):
        if delimiter is None and semicolons:
            line = line.strip().rstrip(";")
            return [t.strip().replace(",", ".") for t in line.split(";")]
        if delimiter is None:
            line = line.rstrip(",;")
            return _AUTO_SPLIT.split(line.strip()) if line.strip() else []
        return [t.strip() for t in line.split(delimiter)]

    _check_text_size(path)
    flat = array("d")  # 8 bytes a value, not a Python float object's 32
    lines = array("q")
    units = array("d")
    width = None
    with open(path, encoding=text_encoding(path), errors="replace", newline=None) as stream:
        for number, raw in enumerate(stream, start=1):
            if skiprows != "auto" and number <= skiprows:
                continue
            line = raw.strip()
            if not line or line.startswith(_COMMENT):
                continue
            shown = repr(line if len(line) <= 60 else line[:57] + "...")
            if "\x00" in line:
                raise _bad(path, f"a NUL byte in the line {shown} (a binary or damaged file)",
                           number)
            if semicolons is None:
                semicolons = ";" in line
            tokens = split(raw.rstrip("\r\n"))
            try:
                row = [_token(t) for t in tokens]
            except ValueError:
                if skiprows == "auto" and not lines and _is_header(tokens):
                    if header is not None:
                        header.append((number, line))
                    continue  # a header line before the first numeric line
                raise _bad(path, f"not a row of numbers: {shown} (header lines, which hold a "
                                 "word, are only allowed before the data; see skiprows, "
                                 "delimiter)", number) from None
            if width is None:
                width = len(row)
            elif (skiprows == "auto" and len(lines) == 1 and width == 1 and len(row) > 1
                  and float(flat[0]).is_integer() and flat[0] >= 0):
                if header is not None:  # a count line (``23``) before the rows: a header
                    header.append((lines[0], f"{int(flat[0])} (a count line)"))
                flat, lines, units, width = array("d"), array("q"), array("d"), len(row)
            elif len(row) != width:
                raise _bad(path, f"{len(row)} values, but the first data row (line "
                                 f"{lines[0]}) has {width}", number)
            flat.extend(row)
            lines.append(number)
            if len(flat) > MAX_POINTS:
                raise _bad(path, f"more than MAX_POINTS = {MAX_POINTS} values: too large "
                                 "for a text table (save it as .npy or .x3p)", number)
            if isinstance(units_of, (int, np.integer)) and not isinstance(units_of, bool) \
                    and -width <= units_of < width:
                units.append(_last_digit_unit(tokens[units_of]))
    if not lines:
        raise _bad(path, "no rows of numbers found")
    values = np.frombuffer(flat, dtype=np.float64).reshape(len(lines), width).copy()
    del flat
    lines = lines.tolist()
    if units_of is None:
        return values, lines
    digits = np.array(units, dtype=np.float64) if len(units) == len(lines) else \
        np.full(len(lines), np.nan)
    return values, lines, digits


def text_encoding(path) -> str:
    """The encoding to read a text file with: ``"utf-16"`` where it starts with a UTF-16
    byte-order mark (spreadsheet exports), else ``"utf-8-sig"`` (UTF-8, with or without its
    mark, which ASCII is too)."""
    try:
        with open(path, "rb") as stream:
            head = stream.read(2)
    except TypeError:
        return "utf-8-sig"  # not a path (an open stream)
    return "utf-16" if head in (b"\xff\xfe", b"\xfe\xff") else "utf-8-sig"


def _check_text_size(path):
    """Refuse a text file larger than :data:`MAX_TEXT_BYTES` before reading a line of it."""
    try:
        size = os.stat(path).st_size
    except (TypeError, ValueError):
        return  # not a path (an open stream): the value count still stops at MAX_POINTS
    if size > MAX_TEXT_BYTES:
        raise _bad(path, f"the file is {size / 2**20:.0f} MiB, more than the "
                         f"{MAX_TEXT_BYTES / 2**20:.0f} MiB allowed for a text table "
                         "(MAX_TEXT_BYTES); save large maps as .npy or .x3p")


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
                 skiprows="auto", unit_scale=1.0, return_digits=False):
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
        return_digits: also return, per point, the unit of the last printed digit of x
            (scaled like x): what :func:`profile_step` needs to tell rounding from an
            irregular grid.

    Returns:
        ``(x, z)`` (or ``(x, z, x_digit_units)``): float64 arrays of shape (n,), ``n >= 2``.
        x is finite and strictly increasing (not necessarily uniform); z may hold NaN for
        missing points.

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
    table = _read_table(path, delimiter=delimiter, skiprows=skiprows,
                        units_of=None if spacing is not None else x_column)
    values, lines = table[0], table[1]
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
    if return_digits:
        return np.ascontiguousarray(x), np.ascontiguousarray(z), table[2] * scales[0]
    return np.ascontiguousarray(x), np.ascontiguousarray(z)


def profile_step(x, digit_units=None, *, path="x"):
    """The step of a profile's x positions, as a regular grid ``x = x0 + i * dx``.

    ``x0`` and ``dx`` are fitted by least squares. Instruments and spreadsheets print x
    rounded (to 0.1 um, or to 6 significant digits), so the grid is accepted when every
    residual stays within the rounding of its printed digits (:data:`ROUNDING_TOLERANCE`
    times the unit of its last digit, ``digit_units``) or within 1e-6 of the step; anything
    larger is an irregular grid and is refused.

    Returns:
        ``(dx, largest residual)``.

    Raises:
        MalformedFileError: naming ``path``: fewer than 2 points, or an irregular grid (the
            message gives the largest residual and the rounding allowed).
    """
    x = np.asarray(x, dtype=np.float64)
    n = x.size
    if n < 2:
        raise _bad(path, f"a profile needs at least 2 points, found {n}")
    i = np.arange(n, dtype=np.float64)
    units = np.zeros(n) if digit_units is None else np.asarray(digit_units, dtype=np.float64)
    units = np.where(np.isfinite(units), units, 0.0)
    # weighted by the printed precision: finely printed points pin the line down
    weights = None if not np.all(units > 0) else 1.0 / units
    dx, x0 = np.polyfit(i, x, 1, w=weights)
    residual = np.abs(x - (x0 + i * dx))
    allowed = np.maximum(1e-6 * abs(dx), ROUNDING_TOLERANCE * units)
    if not dx > 0 or np.any(residual > allowed + 1e-12 * np.abs(x)):
        k = int(np.argmax(residual - allowed))
        steps = np.diff(x)
        raise _bad(path, f"the x column is not a regular grid: x = {float(x[k])!r} (point {k}) is "
                         f"{residual[k]:.3g} off the line x0 + i*dx (dx = {dx:.6g}), more "
                         f"than the rounding of its printed digits allows ({allowed[k]:.3g}); "
                         f"steps from {steps.min():.6g} to {steps.max():.6g}. Give the "
                         "spacing to read the heights alone (--spacing)")
    if residual.max() <= 1e-6 * dx:  # an exact grid: the end-to-end step, free of fit noise
        dx = (x[-1] - x[0]) / (n - 1)
    return float(dx), float(residual.max())


def read_surface(path, *, spacing, delimiter=None, skiprows="auto", unit_scale=1.0,
                 return_header=False):
    """Read a grid of heights from a text / CSV file: row ``iy`` of the data holds
    ``z[iy, 0], z[iy, 1], ...`` (rows are y, columns x).

    Args:
        path: the file.
        spacing: scalar or ``(dy, dx)`` in array order, > 0, in the output unit.
        delimiter, skiprows: see the module docstring.
        unit_scale: > 0, a factor applied to the heights read.
        return_header: also return the header lines skipped, as ``(line number, text)``.

    Returns:
        ``(z, spacing)``: ``z[iy, ix]`` float64 of shape (ny, nx) (NaN: missing points)
        and ``spacing`` as a tuple ``(dy, dx)`` of floats (and the header lines).

    Raises:
        MalformedFileError: naming the file and line: non-numeric data, rows of different
            lengths, infinite heights, more than :data:`MAX_POINTS` points.
        ValueError: a bad parameter (named).
    """
    unit_scale = _scale("unit_scale", unit_scale)
    _, spacing = normalize((1, 1), spacing)
    header = []
    z, lines = _read_table(path, delimiter=delimiter, skiprows=skiprows, header=header)
    if z.size > MAX_POINTS:
        raise _bad(path, f"{z.shape[0]} x {z.shape[1]} points exceed MAX_POINTS = {MAX_POINTS}")
    z *= unit_scale
    _check_heights(path, z, lines)
    spacing = (float(spacing[0]), float(spacing[1]))
    return (z, spacing, header) if return_header else (z, spacing)


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
