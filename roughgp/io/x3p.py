"""ISO 25178-72 ``.x3p`` files read and written in micrometres (the file stores metres).

:func:`read_x3p` reads a conforming file with x3pio and, where x3pio refuses a file for its
form rather than its content (a top folder in the zip, as the R package x3ptools writes it;
a ``main.xml`` without the schema's namespace), reads it with a lenient parser of its own
(:func:`_read_lenient`) that applies the same checks: defusedxml (no entity expansion), the
declared sizes before any allocation, the MD5 checksums where the file has them, and the
data types of the standard (``I`` int16, ``L`` int32, ``F`` float32, ``D`` float64, with the
z axis' increment applied as x3pio applies it, and the valid-points mask of integer data).
The z offset is added to the heights, ``z = raw * increment + offset``, as SurfaceTopography
reads it (openGPS's ``ISO5436-sample4_bin.x3p``: int16 heights with a z offset); the x and y
offsets place the first point: ``meta["offset"]``, its z 0 (the heights hold it). Invalid
points are NaN. :func:`write_x3p` writes through x3pio, in the revision that SurfaceTopography,
surfalize and x3pio all read (:data:`WRITE_REVISION`).

Layout: a surface is ``z[iy, ix]`` (the data file runs x fastest), spacing ``(dy, dx)``.
"""

from __future__ import annotations

import dataclasses
import hashlib
import math
import posixpath
import types
import zipfile
import zlib

import numpy as np

from roughgp.common.checks import profile_or_surface
from roughgp.common.dates import creation_date
from roughgp.common.grid import normalize
from roughgp.common.version import VERSION
from roughgp.io.readers import MAX_POINTS, MalformedFileError

__all__ = ["MAX_XML_BYTES", "LATERAL_RANGE", "Z_RANGE", "WRITE_REVISION", "HeightMap", "read_x3p",
           "write_x3p", "creation_date"]

#: Largest uncompressed ``main.xml`` of an x3p file that is parsed (256 MiB).
MAX_XML_BYTES = 2 ** 28

_UM_PER_M = 1e6
#: zip compression methods Python reads: stored, deflate, bzip2, lzma
_ZIP_METHODS = (zipfile.ZIP_STORED, zipfile.ZIP_DEFLATED, zipfile.ZIP_BZIP2, zipfile.ZIP_LZMA)
_DTYPES = {"I": "<i2", "L": "<i4", "F": "<f4", "D": "<f8"}


def _bad(path, problem: str) -> MalformedFileError:
    return MalformedFileError(f"{path}: {problem}")


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
            first point, micrometres; z is 0: the file's z offset is added to ``z``),
            ``z_offset`` (that z offset, µm), ``creator``, ``date``, ``instrument``,
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
    for info in infos:
        if info.flag_bits & 0x1:
            raise _bad(path, f"the zip member {info.filename!r} is encrypted (password-"
                             "protected); an x3p file's members are not: decrypt it first")
        if info.compress_type not in _ZIP_METHODS:
            raise _bad(path, f"the zip member {info.filename!r} is compressed with method "
                             f"{info.compress_type}, which roughgp cannot decompress (x3p "
                             "files use deflate or none)")
    mains = [i for i in infos if i.filename.replace("\\", "/").split("/")[-1] == "main.xml"]
    if not mains:
        raise _bad(path, "not an x3p file: the zip archive holds no main.xml")
    for info in mains:
        if info.file_size > MAX_XML_BYTES:
            raise _bad(path, f"{info.filename} declares {info.file_size} bytes, more than "
                             f"MAX_XML_BYTES = {MAX_XML_BYTES}")


#: The lateral increments read, metres: 1 pm to 1 m a step (beyond them: a damaged file).
LATERAL_RANGE = (1e-12, 1.0)
#: The z increments read, metres per stored unit (1 for float data, ~1e-9 for integers).
Z_RANGE = (1e-18, 1e3)


def _check_scales(path, lateral, z_scale, z_offset=0.0):
    """Refuse increments outside :data:`LATERAL_RANGE` / :data:`Z_RANGE` (1e300, 1e-320, 0)."""
    for name, d in lateral:
        if not (math.isfinite(d) and LATERAL_RANGE[0] <= abs(d) <= LATERAL_RANGE[1]):
            raise _bad(path, f"the {name} increment {float(d)!r} m is not a usable step: "
                             f"roughgp reads |increment| from {LATERAL_RANGE[0]:g} to "
                             f"{LATERAL_RANGE[1]:g} m")
    if not (math.isfinite(z_scale) and Z_RANGE[0] <= abs(z_scale) <= Z_RANGE[1]):
        raise _bad(path, f"the z increment {float(z_scale)!r} is not a usable height scale: "
                         f"roughgp reads |increment| from {Z_RANGE[0]:g} to {Z_RANGE[1]:g} "
                         "m per stored unit")
    if not (math.isfinite(z_offset) and abs(z_offset) <= 1e3):
        raise _bad(path, f"the z offset {float(z_offset)!r} m is not finite and at most 1e3 m")


def _check_rotation(path, rotation):
    """Refuse a Record1 rotation other than the identity (the grid would not be z[iy, ix])."""
    if rotation is not None and not np.allclose(rotation, np.eye(3), rtol=0, atol=1e-9):
        rows = "; ".join(" ".join(f"{v:.6g}" for v in row) for row in np.asarray(rotation))
        raise _bad(path, f"Record1 rotates the data (Axes/Rotation = [{rows}], not the "
                         "identity): roughgp reads unrotated grids only")


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
                NotImplementedError, RuntimeError, UnicodeDecodeError)
    _check_container(path)
    try:
        info = x3pio.info(path)
    except x3pio.X3pChecksumError as error:
        try:
            other = _checksum_of_another_member(path)
        except (zipfile.BadZipFile, zlib.error, EOFError, RuntimeError) as damaged:
            raise _bad(path, f"not a valid x3p file: {error}; a damaged zip archive "
                             f"({damaged})") from None
        if not other:
            raise _bad(path, f"not a valid x3p file: {error}") from None
        # SurfaceTopography 1.27 writes the data's MD5 (``HASH *bindata/data.bin``) into
        # md5checksum.hex: it names the member it checks, and that member matches
        return _read_lenient(path, layer, why="md5checksum.hex holds the checksum of the "
                                              "data, not of main.xml")
    except x3pio.X3pFormatError as error:  # the form (a top folder, no namespace): lenient
        try:
            return _read_lenient(path, layer, why=None)
        except MalformedFileError as lenient:
            raise _bad(path, f"not a valid x3p file: {error}; read leniently: "
                             f"{str(lenient).split(': ', 1)[-1]}") from None
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
    _check_scales(path, [(name, axis.increment) for name, axis in axes],
                  header.z.increment, float(info.placement.offset[2]))
    _check_rotation(path, info.placement.rotation)
    if min(info.shape, default=0) < 1:
        sizes = ("SizeY", "SizeX") if kind == "SURFACE" else ("SizeX",)
        raise _bad(path, "declares an empty matrix (" + ", ".join(
            f"{n} = {v}" for n, v in zip(sizes, info.shape)) + ")")
    points = math.prod(info.shape) * info.layer_count
    if points > MAX_POINTS:
        shape = " x ".join(str(n) for n in info.shape)
        raise _bad(path, f"declares {info.layer_count} layer(s) of {shape} = {points} points, "
                         f"more than MAX_POINTS = {MAX_POINTS}")
    if not (isinstance(layer, (int, np.integer)) and 0 <= layer < info.layer_count):
        raise ValueError(f"layer must be an integer in [0, {info.layer_count}) for "
                         f"{path}, got {layer!r}")

    try:
        file = x3pio.read(path)
    except expected as error:
        raise _bad(path, f"not a valid x3p file: {error}") from None
    z_offset = float(info.placement.offset[2]) * _UM_PER_M  # x3pio leaves it out of z
    z = np.array(file.layers[layer].z, dtype=np.float64) * _UM_PER_M + z_offset
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
        "offset": (*(float(v) * _UM_PER_M for v in info.placement.offset[:2]), 0.0),
        "z_offset": z_offset,
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


#: The ``Revision`` that :func:`write_x3p` writes: ISO 25178-72:2017 under its openGPS name,
#: the one SurfaceTopography 1.27 requires and surfalize and x3pio read too (the newer
#: ``ISO25178-72:2017/DAM1`` of Amd 1:2020, x3pio's default, is refused by SurfaceTopography).
WRITE_REVISION = "ISO5436 - 2000"


def write_x3p(path, z, spacing, *, comment=None, creator=None, offset=None, date=None) -> None:
    """Write a profile ``z[ix]`` or a surface ``z[iy, ix]`` to an ISO 25178-72 ``.x3p`` file.

    The layout is that of :func:`read_x3p`: heights and ``spacing`` (scalar or array order,
    ``(dy, dx)``) in micrometres; they are stored in metres (times 1e-6) as float64 with
    x3pio's documented ``x3pio.write``, so ``read_x3p`` gives them back to float rounding.
    The file follows :data:`WRITE_REVISION` (read by SurfaceTopography, surfalize and x3pio),
    with the MD5 checksums of ``main.xml`` and of the data. NaN marks a missing point;
    infinite heights are refused. ``Record2`` names roughgp as the software (x3p's record of
    data not measured), with ``creator`` and ``comment`` if given; ``offset`` (x, y, z in
    micrometres, as ``read_x3p``'s ``meta["offset"]``) places the first point, as the axes'
    offsets of the input file did. ``date``: the creation date (:func:`creation_date`:
    ``SOURCE_DATE_EPOCH`` or now by default).

    Raises:
        ValueError: ``z`` not 1-D / 2-D or holding infinite values, a bad ``spacing`` or a
            non-finite ``offset``.
    """
    x3pio = _x3pio()
    arr = profile_or_surface(z)
    _, spacing = normalize(arr.shape, spacing)
    metadata = x3pio.Metadata.for_software("roughgp", VERSION, date=creation_date(date))
    metadata.comment = None if comment is None else str(comment)
    metadata.creator = None if creator is None else str(creator)
    options = {"metadata": metadata, "revision": x3pio.Revision(WRITE_REVISION)}
    if offset is not None:
        shift = np.asarray(offset, dtype=np.float64).reshape(-1)
        if shift.shape != (3,) or not np.all(np.isfinite(shift)):
            raise ValueError(f"offset must be three finite numbers (x, y, z in um), got "
                             f"{offset!r}")
        options.update(placement=x3pio.Placement(offset=shift / _UM_PER_M),
                       coordinate_system=x3pio.CoordinateSystem.VIEW)
    heights = arr / _UM_PER_M
    if arr.ndim == 1:
        x3pio.write(path, heights, x_scale=float(spacing[0]) / _UM_PER_M, **options)
    else:
        x3pio.write(path, heights, x_scale=float(spacing[1]) / _UM_PER_M,
                    y_scale=float(spacing[0]) / _UM_PER_M, **options)


# --------------------------------------------------------------------------- lenient reader

def _local(tag: str) -> str:
    return tag.rsplit("}", 1)[-1]


def _find(element, *names):
    """The first descendant path ``names`` of ``element``, ignoring XML namespaces."""
    for name in names:
        if element is None:
            return None
        element = next((c for c in element if _local(c.tag) == name), None)
    return element


def _value(element, *names, default=None):
    found = _find(element, *names)
    text = None if found is None else (found.text or "").strip()
    return text if text else default


def _number(path, element, names, default=None):
    text = _value(element, *names)
    if text is None:
        if default is None:
            raise _bad(path, f"main.xml has no {'/'.join(names)}")
        return default
    try:
        return float(text)
    except ValueError:
        raise _bad(path, f"main.xml: {'/'.join(names)} is not a number: {text[:40]!r}") from None


def _member(archive, root, link):
    """The zip member that ``link`` (relative to the x3p root folder) names."""
    name = posixpath.normpath(posixpath.join(root, link.replace("\\", "/")))
    if name.startswith("..") or name.startswith("/"):
        return None
    names = {i.filename: i for i in archive.infolist()}
    return names.get(name)


def _checked_bytes(path, archive, info, expected_md5, what, limit):
    if info.file_size > limit:
        raise _bad(path, f"{what} declares {info.file_size} bytes, more than the "
                         f"{limit} its declared size needs")
    data = archive.read(info)
    if expected_md5 and hashlib.md5(data).hexdigest().lower() != expected_md5.lower():
        raise _bad(path, f"the MD5 checksum of {what} does not match the file "
                         "(damaged or edited)")
    return data


def _stated_checksum(archive, root_dir):
    """``(md5, member name)`` from md5checksum.hex (``HASH *name``; no name: main.xml), or
    None where the archive has no (small) checksum file."""
    checksum_file = _member(archive, root_dir, "md5checksum.hex")
    if checksum_file is None or checksum_file.file_size >= 4096:
        return None
    stated = archive.read(checksum_file).decode("ascii", "replace").split()
    if not stated:
        return None
    return stated[0].lower(), (stated[1].lstrip("*") if len(stated) > 1 else "main.xml")


def _checksum_of_another_member(path) -> bool:
    """Whether md5checksum.hex names a member other than main.xml, whose MD5 it matches."""
    with zipfile.ZipFile(path) as archive:
        stated = _stated_checksum(archive, "")
        if stated is None or posixpath.basename(stated[1]) == "main.xml":
            return False
        info = _member(archive, "", stated[1])
        if info is None or info.file_size > MAX_POINTS * 8:
            return False
        return hashlib.md5(archive.read(info)).hexdigest().lower() == stated[0]


def _read_lenient(path, layer=0, why=None) -> HeightMap:
    """Read an x3p file that x3pio refuses for its form (module docstring); a damaged zip
    member is a :class:`MalformedFileError`."""
    try:
        return _read_lenient_archive(path, layer, why)
    except (zipfile.BadZipFile, zlib.error, EOFError, RuntimeError, NotImplementedError) as error:
        raise _bad(path, f"not a valid x3p file: a damaged zip archive ({error})") from None


def _read_lenient_archive(path, layer, why) -> HeightMap:
    from defusedxml import ElementTree

    try:
        archive = zipfile.ZipFile(path)
    except zipfile.BadZipFile as error:
        raise _bad(path, f"not an x3p file: not a (valid) zip archive ({error})") from None
    with archive:
        mains = [i for i in archive.infolist() if not i.is_dir()
                 and posixpath.basename(i.filename.replace("\\", "/")) == "main.xml"
                 and not i.filename.startswith("__MACOSX")]
        if len(mains) != 1:
            raise _bad(path, f"holds {len(mains)} main.xml files, expected one")
        main = mains[0]
        root_dir = posixpath.dirname(main.filename.replace("\\", "/"))
        xml = archive.read(main)
        stated = _stated_checksum(archive, root_dir)
        if stated is not None and posixpath.basename(stated[1]) == "main.xml" \
                and hashlib.md5(xml).hexdigest().lower() != stated[0]:
            raise _bad(path, "the MD5 checksum of main.xml does not match md5checksum.hex")
        try:
            doc = ElementTree.fromstring(xml)
        except Exception as error:  # defusedxml's refusals and XML syntax errors
            raise _bad(path, f"main.xml is not acceptable XML ({type(error).__name__}: "
                             f"{error})") from None
        if _local(doc.tag) != "ISO5436_2" and _local(doc.tag) != "ISO5436":
            raise _bad(path, f"main.xml has the root element <{_local(doc.tag)}>, not "
                             "<ISO5436_2>")
        r1, r3 = _find(doc, "Record1"), _find(doc, "Record3")
        kind = (_value(r1, "FeatureType") or "").upper()
        if kind not in ("SUR", "PRF"):
            raise _bad(path, f"holds feature type {kind or '(none)'}: only profiles (PRF) and "
                             "surfaces (SUR) on a regular grid are read")
        axes = _find(r1, "Axes")
        for name in ("CX", "CY") if kind == "SUR" else ("CX",):
            if (_value(axes, name, "AxisType") or "I").upper() != "I":
                raise _bad(path, f"the {name[1].lower()} axis is absolute (irregular "
                                 "positions): only regular grids are read")
        dx = _number(path, axes, ("CX", "Increment"))
        dy = _number(path, axes, ("CY", "Increment"), default=dx) if kind == "SUR" else dx
        dtype = (_value(axes, "CZ", "DataType") or "D").upper()
        if dtype not in _DTYPES:
            raise _bad(path, f"z data type {dtype!r} is not one of I, L, F, D")
        z_scale = _number(path, axes, ("CZ", "Increment"), default=1.0)
        z_offset = _number(path, axes, ("CZ", "Offset"), default=0.0)
        _check_scales(path, (("x", dx), ("y", dy)), z_scale, z_offset)
        rotation = _find(axes, "Rotation")
        if rotation is not None:
            _check_rotation(path, [[_number(path, rotation, (f"r{i}{j}",), default=float(i == j))
                                    for j in (1, 2, 3)] for i in (1, 2, 3)])
        size = [int(_number(path, r3, ("MatrixDimension", n), default=1.0))
                for n in ("SizeX", "SizeY", "SizeZ")]
        if min(size) < 1:
            raise _bad(path, "declares an empty matrix (" + ", ".join(
                f"{n} = {v}" for n, v in zip(("SizeX", "SizeY", "SizeZ"), size)) + ")")
        points = math.prod(size)
        if points > MAX_POINTS:
            raise _bad(path, f"declares {size[2]} layer(s) of {size[1]} x {size[0]} = "
                             f"{points} points, more than MAX_POINTS = {MAX_POINTS}")
        if not (isinstance(layer, (int, np.integer)) and 0 <= layer < size[2]):
            raise ValueError(f"layer must be an integer in [0, {size[2]}) for {path}, "
                             f"got {layer!r}")
        link = _value(r3, "DataLink", "PointDataLink")
        info = None if link is None else _member(archive, root_dir, link)
        if info is None:
            raise _bad(path, f"the point data {link!r} named in main.xml is not in the archive")
        item = np.dtype(_DTYPES[dtype])
        raw = _checked_bytes(path, archive, info, _value(r3, "DataLink", "MD5ChecksumPointData"),
                             link, points * item.itemsize)
        if len(raw) != points * item.itemsize:
            raise _bad(path, f"{link} holds {len(raw)} bytes; {size[1]} x {size[0]} x "
                             f"{size[2]} points of {item} need {points * item.itemsize}")
        values = np.frombuffer(raw, dtype=item).astype(np.float64)
        values = values * z_scale + z_offset  # as ISO 5436-2 and SurfaceTopography
        if dtype in ("I", "L"):
            valid_link = _value(r3, "DataLink", "ValidPointsLink") or _value(r3, "ValidPointsLink")
            valid = None if valid_link is None else _member(archive, root_dir, valid_link)
            if valid is not None:
                bits = np.frombuffer(_checked_bytes(path, archive, valid, None, valid_link,
                                                    (points + 7) // 8), dtype=np.uint8)
                mask = np.unpackbits(bits, bitorder="little")[:points].astype(bool)
                if mask.size == points:
                    values[~mask] = np.nan
        values[~np.isfinite(values)] = np.nan
        z = values.reshape(size[2], size[1], size[0])[layer] * _UM_PER_M
        if kind == "PRF":
            z = z.reshape(-1)
        if dx < 0:
            z = np.flip(z, axis=-1)
        if kind == "SUR" and dy < 0:
            z = np.flip(z, axis=0)
        spacing = (abs(dy) * _UM_PER_M, abs(dx) * _UM_PER_M) if kind == "SUR" \
            else (abs(dx) * _UM_PER_M,)
        r2 = _find(doc, "Record2")
        instrument = _find(r2, "Instrument")
        offsets = (*(_number(path, axes, (n, "Offset"), default=0.0) * _UM_PER_M
                     for n in ("CX", "CY")), 0.0)
        meta = {
            "feature_type": "surface" if kind == "SUR" else "profile",
            "revision": _value(r1, "Revision"), "layer_count": size[2], "offset": offsets,
            "z_offset": z_offset * _UM_PER_M,
            "creator": _value(r2, "Creator"), "date": _value(r2, "Date"),
            "instrument": None if instrument is None else " ".join(
                v for v in (_value(instrument, n) for n in
                            ("Manufacturer", "Model", "Serial", "Version")) if v),
            "probing_system": " ".join(v for v in (_value(r2, "ProbingSystem", n)
                                                   for n in ("Type", "Identification")) if v)
            or None,
            "comment": _value(r2, "Comment"),
            "reader": "lenient (not read by x3pio: " + (
                why or ("a top folder in the zip" if root_dir else "its form")) + ")",
        }
    return HeightMap(np.ascontiguousarray(z), spacing, "um", types.MappingProxyType(meta))
