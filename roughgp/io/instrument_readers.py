"""SurfaceTopography's reader of one file format, imported without the rest of the package.

``import SurfaceTopography`` runs the package's ``__init__``, which imports all of its readers
and analyses (pandas, matplotlib, openpyxl, h5py, scipy.signal, scipy.stats: 1-1.6 s on the
2-core machine), while one binary format needs one module (``SurfaceTopography.IO.OPD``: about
0.1 s beyond NumPI's scipy.optimize). :func:`open_by_extension` opens a file with the reader
that :data:`READER_BY_EXTENSION` names for its extension, importing that reader's module only:
the packages ``SurfaceTopography`` and ``SurfaceTopography.IO`` are put in ``sys.modules`` as
:class:`_DeferredPackage` objects, which run their real ``__init__`` the first time anything
reads an attribute they do not yet have (``SurfaceTopography.IO.open_topography``, ...), so a
later ``import SurfaceTopography`` in the same process gets the whole package as usual.
``NuMPI`` (SurfaceTopography's MPI layer) is deferred the same way: its ``__init__`` imports
``NuMPI.Optimization`` and with it ``scipy.optimize`` (0.2-0.45 s on the 2-core machine),
which no reader uses; a topography needs only ``NuMPI.MPI`` and ``NuMPI.Tools``
(:func:`_defer_numpi`).

The table lists only extensions that one reader claims and that no reader before it in
SurfaceTopography's detection order claims (``tests/metrology/test_instrument_readers.py``
checks it against ``SurfaceTopography.IO.readers``). A file the named reader does not open
(wrong magic, damaged, another format under that name) gets ``None``: the caller detects the
format by content through the whole package, as before.
"""

from __future__ import annotations

import importlib
import importlib.util
import sys
import types
import warnings
from pathlib import Path

__all__ = ["READER_BY_EXTENSION", "reader_class", "open_by_extension"]

#: File extension -> (module of ``SurfaceTopography.IO``, reader class): the binary formats
#: whose extension one reader claims (text formats go through roughgp's own readers first).
READER_BY_EXTENSION = {
    "opd": ("OPD", "OPDReader"),
    "opdx": ("OPDx", "OPDxReader"),
    "sur": ("SUR", "SURReader"),
    "al3d": ("AL3D", "AL3DReader"),
    "frt": ("FRT", "FRTReader"),
    "nms": ("NMS", "NMSReader"),
    "tmd": ("TMD", "TMDReader"),
    "mdt": ("MDT", "MDTReader"),
    "plu": ("PLU", "PLUReader"),
    "plux": ("PLUX", "PLUXReader"),
    "mnt": ("MNT", "MNTReader"),
    "zon": ("ZON", "ZONReader"),
    "vk3": ("VK", "VKReader"),
    "vk4": ("VK", "VKReader"),
    "vk6": ("VK", "VKReader"),
    "vk7": ("VK", "VKReader"),
    "gwy": ("GWY", "GWYReader"),
    "ibw": ("IBW", "IBWReader"),
    "mi": ("MI", "MIReader"),
    "lext": ("LEXT", "LEXTReader"),
    "os3d": ("OS3D", "OS3DReader"),
}


class _DeferredPackage(types.ModuleType):
    """A package in ``sys.modules`` whose ``__init__`` runs on the first attribute it lacks
    (its submodules import without it: the import system needs only ``__path__``)."""

    def __getattr__(self, name):
        state = self.__dict__
        if state.get("_roughgp_running"):
            raise AttributeError(name)
        state["_roughgp_running"] = True
        self.__class__ = types.ModuleType  # from now on an ordinary module
        try:
            self.__spec__.loader.exec_module(self)
        finally:
            del state["_roughgp_running"]
        return getattr(self, name)


def _defer(name: str) -> None:
    """Put package ``name`` in ``sys.modules`` without running its ``__init__`` (unless it is
    there already)."""
    if name in sys.modules:
        return
    spec = importlib.util.find_spec(name)
    package = _DeferredPackage(name)
    package.__spec__, package.__loader__ = spec, spec.loader
    package.__path__ = list(spec.submodule_search_locations)
    package.__file__, package.__package__ = spec.origin, name
    sys.modules[name] = package
    parent, _, child = name.rpartition(".")
    if parent:
        setattr(sys.modules[parent], child, package)


def _defer_numpi() -> None:
    """Put ``NuMPI`` in ``sys.modules`` deferred, with the ``MPI`` its ``__init__`` would set
    (mpi4py's where it is installed, else NuMPI's stub), so that SurfaceTopography's
    ``from NuMPI import MPI`` does not run the ``__init__`` (and its scipy.optimize); any
    other attribute runs it."""
    if "NuMPI" in sys.modules:
        return
    _defer("NuMPI")
    try:
        from mpi4py import MPI
    except ImportError:
        MPI = importlib.import_module("NuMPI.MPIStub")
    sys.modules["NuMPI"].MPI = MPI


def reader_class(extension: str):
    """SurfaceTopography's reader class for a file extension of :data:`READER_BY_EXTENSION`
    (without a dot, any case), its module imported alone; ``None`` for other extensions."""
    entry = READER_BY_EXTENSION.get(extension.lower())
    if entry is None:
        return None
    module, name = entry
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        _defer_numpi()
        _defer("SurfaceTopography")
        _defer("SurfaceTopography.IO")
        return getattr(importlib.import_module(f"SurfaceTopography.IO.{module}"), name)


def open_by_extension(path):
    """The reader of :data:`READER_BY_EXTENSION` for ``path``'s extension, opened on it, or
    ``None`` when the table names none or that reader does not open the file (the caller then
    detects the format by content with ``SurfaceTopography.IO.open_topography``)."""
    cls = reader_class(Path(str(path)).suffix.lstrip("."))
    if cls is None:
        return None
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            return cls(str(path))
    except Exception:  # noqa: BLE001 - any failure: detection by content says what is wrong
        return None
