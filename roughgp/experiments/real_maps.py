"""The open real measurements in ``data/``: which file, from which instrument, in which unit.

One list for every chapter and test that runs over real files (provenance and licences:
``data/README.md``). :data:`REAL_MAPS` holds the areal maps, :data:`REAL_PROFILES` the
profiles. Each entry says the instrument as the file or its source states it, the kind of
instrument (``technique``), the height unit the file itself states (``unit``: the reader
converts from it to µm), and whether the file is the instrument's original bytes or a crop
that roughgp wrote (``source``: the original it was cropped from).
"""

from __future__ import annotations

import dataclasses
from pathlib import Path

from roughgp.io.measurement import read_measurement

__all__ = ["DATA", "RealFile", "REAL_MAPS", "REAL_PROFILES", "real_file", "crop_window",
           "central_crop"]

#: the folder of the open measurements
DATA = Path(__file__).resolve().parents[2] / "data"


@dataclasses.dataclass(frozen=True)
class RealFile:
    """An open measurement in ``data/``.

    Attributes:
        name: the file's name in ``data/``.
        instrument: the instrument (vendor, model) as the file or its source states it.
        technique: the kind of instrument: ``"AFM"``, ``"confocal"``,
            ``"white-light interferometer"``, ``"focus variation"``, ``"stylus"``,
            ``"unstated"``.
        unit: the height unit the file states (an x3p stores metres).
        source: ``"original"`` (the instrument software's bytes, unchanged) or the name of
            the original that roughgp cropped this file from (``data/README.md`` says how).
        window: for a crop, ``(first row, first column, points)``: the square of the
            original's heights (``z[iy, ix]`` as roughgp reads it) that the crop holds.
    """

    name: str
    instrument: str
    technique: str
    unit: str
    source: str = "original"
    window: tuple | None = None

    @property
    def path(self) -> Path:
        """The file's path."""
        return DATA / self.name


#: The areal maps (surfaces): 18 files, 11 originals and 7 crops.
REAL_MAPS = (
    RealFile("sample-land.x3p", "Sensofar S neox (via x3ptools)", "confocal", "m"),
    RealFile("sur-2.sur", "Digital Surf (MountainsMap export)", "unstated", "mm"),
    RealFile("opd-1.opd", "Veeco/Bruker Wyko", "white-light interferometer", "mm"),
    RealFile("di-1.di", "Bruker Dimension V (NanoScope)", "AFM", "nm"),
    RealFile("di-3.di", "Bruker Dimension Icon (NanoScope)", "AFM", "nm"),
    RealFile("al3d-1.al3d", "Alicona InfiniteFocus", "focus variation", "m"),
    RealFile("nms-1.nms", "NanoFocus µsurf", "confocal", "µm"),
    RealFile("frt-2.frt", "FRT MicroProf", "unstated", "m"),
    RealFile("tmd-1.tmd", "TrueMap", "unstated", "mm"),
    RealFile("top-1.top", "Nanotec (WSxM)", "AFM", "nm"),
    RealFile("matrix-3.txt", "Gwyddion text export of an AFM's ZSensor channel", "AFM", "m"),
    RealFile("nid-1-crop.x3p", "Nanosurf DriveAFM", "AFM", "m", "nid-1.nid", (0, 0, 256)),
    RealFile("mnt-2-crop.x3p", "MountainsMap", "unstated", "m", "mnt-2.mnt", (528, 0, 256)),
    RealFile("frt-1-crop.x3p", "FRT MicroProf", "unstated", "m", "frt-1.frt", (0, 0, 256)),
    RealFile("ibw-1-crop.x3p", "Asylum Research Cypher", "AFM", "m", "spot_1-1000nm.ibw",
             (0, 0, 256)),
    RealFile("mi-1-crop.x3p", "Molecular Imaging / Agilent", "AFM", "m", "mi-1.mi", (0, 0, 256)),
    RealFile("ps-1-crop.x3p", "Park Systems", "AFM", "m", "example_ps.tiff", (128, 128, 256)),
    RealFile("bcrf-1-crop.x3p", "BCR-STM format (instrument unstated)", "unstated",
             "m", "bcrf-1.bcrf", (172, 352, 256)),
)

#: The profiles (``csv-2.csv``, 8 points, and ``xy-2.txt``, irregular x, are in ``data/`` to
#: test the readers, not as measurements to model).
REAL_PROFILES = (
    RealFile("dektak-1.csv", "Bruker Dektak", "stylus", "µm"),
    RealFile("opdx-3.opdx", "Bruker Dektak", "stylus", "µm"),
    RealFile("xy-4.txt", "text export (instrument unstated)", "unstated", "µm"),
    RealFile("hfm-1.hfm", "text export (instrument unstated)", "unstated", "mm"),
)


def real_file(name: str) -> RealFile:
    """The entry of :data:`REAL_MAPS` or :data:`REAL_PROFILES` named ``name``."""
    for entry in REAL_MAPS + REAL_PROFILES:
        if entry.name == name:
            return entry
    known = ", ".join(e.name for e in REAL_MAPS + REAL_PROFILES)
    raise ValueError(f"name must be one of the files in data/ ({known}), got {name!r}")


def crop_window(shape, size) -> tuple:
    """``(first row, first column, rows, columns)`` of the central ``size`` x ``size`` points
    of a map of ``shape`` (the whole of an axis shorter than ``size``)."""
    if int(size) < 16:
        raise ValueError(f"size must be >= 16 points, got {size!r}")
    rows, cols = (min(int(n), int(size)) for n in shape)
    return ((shape[0] - rows) // 2, (shape[1] - cols) // 2, rows, cols)


def central_crop(name, size):
    """``(heights, spacing, window)``: the :func:`crop_window` of the map ``name`` of data/."""
    m = read_measurement(real_file(name).path)
    r0, c0, rows, cols = crop_window(m.z.shape, size)
    return m.z[r0:r0 + rows, c0:c0 + cols], m.spacing, (r0, c0, rows, cols)
