"""Instrument files of every common format, through SurfaceTopography (MIT, maintained).

SurfaceTopography detects the format by content (Digital Surf ``.sur``, Wyko ``.opd``,
NanoScope ``.di``, Sensofar ``.plu`` / ``.plux``, Zygo ``.datx`` and MetroPro ``.dat``,
MountainsMap ``.mnt``, NanoFocus ``.nms``, Keyence ``.vk4``, ``.sdf``, Gwyddion ``.gwy`` and
about thirty more: :func:`instrument_formats`). :func:`read_instrument` converts what it
returns to roughgp's conventions: heights and spacing in micrometres from the file's own unit,
masked (unmeasured) points as NaN, and the layout ``z[iy, ix]`` (SurfaceTopography's
``heights()`` is ``[ix, iy]``: transposed here), spacing ``(dy, dx)``.
"""

from __future__ import annotations

import struct
import types
import warnings
from pathlib import Path

import numpy as np

from roughgp.io.instrument_readers import open_by_extension
from roughgp.io.readers import MAX_POINTS, MalformedFileError, profile_step
from roughgp.io.x3p import HeightMap

__all__ = ["UM_PER_UNIT", "NMS_SPACING_OFFSET", "read_instrument", "instrument_formats"]

#: Micrometres per length unit, for the units SurfaceTopography reports.
UM_PER_UNIT = {"km": 1e9, "m": 1e6, "cm": 1e4, "mm": 1e3, "µm": 1.0, "um": 1.0, "μm": 1.0,
               "nm": 1e-3, "Å": 1e-4, "A": 1e-4, "pm": 1e-6}


def _topography_io():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        import SurfaceTopography.IO as io  # imported here: only instrument files need it
    return io


def instrument_formats() -> list[tuple[str, str]]:
    """``(format, name)`` of every reader of SurfaceTopography, e.g. ``("sur", "Digital
    Surf SUR")``."""
    io = _topography_io()
    out = []
    for reader in io.readers:
        try:
            out.append((str(reader.format()), str(reader.name())))
        except Exception:  # noqa: BLE001 - a reader without a name is left out of the list
            continue
    return out


def _factor(path, unit, given):
    if given is not None:
        if given not in UM_PER_UNIT:
            raise ValueError(f"unit must be one of {', '.join(UM_PER_UNIT)}, got {given!r}")
        return UM_PER_UNIT[given], f"{given} (as given)"
    if unit is None:
        raise MalformedFileError(f"{path}: the file states no length unit; give the unit "
                                 f"(one of {', '.join(UM_PER_UNIT)})")
    if unit not in UM_PER_UNIT:
        raise MalformedFileError(f"{path}: the file's unit {unit!r} is not a length unit "
                                 f"roughgp knows ({', '.join(UM_PER_UNIT)})")
    return UM_PER_UNIT[unit], f"{unit} (from the file)"


def _reader_named_by(path) -> str | None:
    """The name of SurfaceTopography's reader whose extensions include the file's, if any."""
    ext = Path(str(path)).suffix.lower().lstrip(".")
    for reader in _topography_io().readers:
        try:
            if ext and ext in [str(e).lower() for e in (reader.file_extensions() or ())]:
                return str(reader.name())
        except Exception:  # noqa: BLE001 - a reader without extensions names none
            continue
    return None


def _unreadable(path, error, reader=None) -> MalformedFileError:
    """A reader's failure said as what is wrong with the file (its own words shortened to
    printable text: some quote the file's bytes)."""
    text = str(error)
    if "physical_sizes" in text and "could not be extracted" in text:
        return MalformedFileError(f"{path}: cannot be read: the file states no lateral size "
                                  "(no pixel size or field width), so it is empty, damaged, "
                                  "or not the format it was taken for")
    text = "".join(c if c.isprintable() else "?" for c in text)
    text = text if len(text) <= 160 else text[:157] + "..."
    by = f" ({type(reader).__name__})" if reader is not None else ""
    return MalformedFileError(f"{path}: cannot be read: SurfaceTopography's reader{by} failed "
                              f"on its content ({type(error).__name__}: {text}); the file is "
                              "damaged or truncated, or not the format it was taken for")


#: NanoFocus ``.nms``: the byte offset of the two float64 pixel sizes (x, y) in the header.
#: They are in nm: 312.5 in ``nms-1.nms`` is a 0.3125 µm step (a 160 µm field of 512 points,
#: a confocal microscope's), as surfalize 0.19 reads it; SurfaceTopography 1.27 reads them as
#: mm (a 160 m field).
NMS_SPACING_OFFSET = 1376


def _nms_spacing(path) -> tuple[float, float]:
    """``(dy, dx)`` in µm from a NanoFocus ``.nms`` header (:data:`NMS_SPACING_OFFSET`)."""
    with open(path, "rb") as stream:
        stream.seek(NMS_SPACING_OFFSET)
        raw = stream.read(16)
    if len(raw) != 16:
        raise MalformedFileError(f"{path}: truncated NanoFocus header (no pixel size at byte "
                                 f"{NMS_SPACING_OFFSET})")
    dx_nm, dy_nm = struct.unpack("<2d", raw)
    return dy_nm * 1e-3, dx_nm * 1e-3


#: the first line of an HFM profile (x, height and a validity flag per row, ``;``-separated)
HFM_HEADER = "X;Y;valid"


def _hfm_validity(path, n_points):
    """The rows of an HFM file that hold a measured height (its ``valid`` column: 1 measured,
    0 not), which SurfaceTopography's reader leaves out (it reads the first two columns
    only, so an unmeasured row's placeholder height was read as measured); None for a file
    that is no HFM file."""
    with open(path, "rb") as stream:
        if stream.readline().strip() != HFM_HEADER.encode():
            return None
    try:
        flags = np.loadtxt(path, delimiter=";", skiprows=2, usecols=2, ndmin=1)
    except (ValueError, IndexError) as error:
        raise MalformedFileError(f"{path}: its 'valid' column cannot be read ({error})") \
            from None
    binary = bool(np.isin(flags, (0.0, 1.0)).all())
    if flags.size != n_points or not binary:
        raise MalformedFileError(f"{path}: its 'valid' column must hold 1 (measured) or 0 "
                                 f"(not) for each of the {n_points} points read, got "
                                 f"{flags.size} values"
                                 + ("" if binary else " with others than 0 and 1"))
    return flags == 1.0


def _open_by_detection(path):
    """SurfaceTopography's reader of ``path``, the format detected by content (the whole
    package imported); a :class:`MalformedFileError` saying what is wrong when none opens it."""
    io = _topography_io()
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            return io.open_topography(str(path))
    except io.CannotDetectFileFormat:
        named = _reader_named_by(path)
        if named is not None:
            raise MalformedFileError(f"{path}: not readable as {named} (the format its "
                                     "extension names): its content matches no format "
                                     "SurfaceTopography reads; truncated or damaged?") from None
        raise MalformedFileError(f"{path}: not a format that roughgp or SurfaceTopography "
                                 "reads (no reader recognises its content)") from None
    except Exception as error:  # noqa: BLE001 - a reader's own failure, said with the file
        raise _unreadable(path, error) from None


def read_instrument(path, *, channel=0, unit=None) -> HeightMap:
    """Read a profile or a surface from an instrument file, in micrometres.

    Args:
        path: the file (any format SurfaceTopography detects).
        channel: index of the data channel (e.g. height, phase, amplitude of an AFM file);
            ``meta["channels"]`` lists them.
        unit: the file's length unit where it states none (or to override it).

    Returns:
        A :class:`~roughgp.io.x3p.HeightMap`: ``z[ix]`` or ``z[iy, ix]`` in µm with
        NaN at unmeasured points, ``spacing`` in µm in array order, and ``meta`` (the reader,
        the channel and its name, the file's unit, the instrument as SurfaceTopography reports
        it). A NanoFocus ``.nms`` file's spacing is read from its header in nm
        (:data:`NMS_SPACING_OFFSET`), not as SurfaceTopography reads it.

    Raises:
        MalformedFileError: naming the file: no reader recognises it (a file whose extension
            names a format that its content does not match is said to be damaged or
            truncated), it cannot be read (what is wrong, not the reader's exception), it
            holds no data channel, it states no unit (and none is given), or it holds more
            than :data:`MAX_POINTS`.
    """
    reader = open_by_extension(path)  # the one reader's module, without the whole package
    if reader is None:
        reader = _open_by_detection(path)
    try:
        names = [str(c.name) for c in reader.channels]
    except Exception as error:  # noqa: BLE001
        raise _unreadable(path, error, reader) from None
    if not names:
        raise MalformedFileError(f"{path}: holds no data channel ({type(reader).__name__} "
                                 "found none: truncated or damaged?)")
    if not (isinstance(channel, (int, np.integer)) and 0 <= channel < len(names)):
        raise ValueError(f"channel must be an integer in [0, {len(names)}) for {path} "
                         f"(channels: {', '.join(names)}), got {channel!r}")
    try:
        points = int(np.prod(reader.channels[channel].nb_grid_pts))
    except Exception as error:  # noqa: BLE001
        raise _unreadable(path, error, reader) from None
    if points > MAX_POINTS:
        raise MalformedFileError(f"{path}: {points} points exceed MAX_POINTS = {MAX_POINTS}")
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            topography = reader.topography(channel_index=int(channel))
            heights = topography.heights()
            file_unit = topography.unit
            uniform = getattr(topography, "is_uniform", True)
            pixel = (np.asarray(topography.pixel_size, dtype=np.float64) if uniform
                     else np.asarray(topography.positions(), dtype=np.float64))
    except Exception as error:  # noqa: BLE001 - a reader's own failure, reported with the file
        raise _unreadable(path, error, reader) from None
    factor, unit_source = _factor(path, file_unit, unit)
    z = np.ma.filled(np.ma.asarray(heights, dtype=np.float64), np.nan) * factor
    z[~np.isfinite(z)] = np.nan
    if reader.format() == "xyz" and z.ndim == 1:
        valid = _hfm_validity(path, z.size)
        if valid is not None:
            z[~valid] = np.nan
    if uniform:
        pixel = np.atleast_1d(pixel) * factor
    else:  # a line scan with x positions from the file: regular (to 1e-6) or refused
        step, _ = profile_step(pixel * factor, path=path)
        pixel = np.array([step])
    if z.ndim == 2:
        z = z.T  # SurfaceTopography: [ix, iy]; roughgp: [iy, ix]
        spacing = (float(pixel[1]), float(pixel[0]))
    else:
        spacing = (float(pixel[0]),)
    if reader.format() == "nms" and z.ndim == 2:
        spacing = _nms_spacing(path)
    info = dict(getattr(topography, "info", {}) or {})
    instrument = info.get("instrument", {}) if isinstance(info.get("instrument"), dict) else {}
    meta = {
        "feature_type": "surface" if z.ndim == 2 else "profile",
        "reader": f"SurfaceTopography {type(reader).__name__} ({reader.format()})"
        + (", the spacing from the header in nm (roughgp)" if reader.format() == "nms" else ""),
        "channel": int(channel), "channel_name": names[channel], "channels": tuple(names),
        "unit": unit_source,
        "instrument": " ".join(str(instrument[k]) for k in ("vendor", "name") if k in instrument)
        or None,
        "date": info.get("acquisition_time"),
    }
    return HeightMap(np.ascontiguousarray(z), spacing, "um", types.MappingProxyType(meta))
