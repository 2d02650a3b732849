"""The one-reader fast path of roughgp.io.instrument_readers: its table agrees with
SurfaceTopography's own detection, it reads the files the same, and it does not import the
whole package."""

import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from roughgp.io import instrument_readers, instruments

ROOT = Path(__file__).resolve().parents[2]
DATA = ROOT / "data"


def test_each_extension_is_claimed_by_its_reader_and_by_no_reader_detected_before_it():
    import SurfaceTopography.IO as io

    for extension, (module, name) in instrument_readers.READER_BY_EXTENSION.items():
        cls = instrument_readers.reader_class(extension)
        assert cls.__name__ == name and cls.__module__ == f"SurfaceTopography.IO.{module}"
        assert cls in io.readers, f"{name} is not one of SurfaceTopography's readers"
        position = io.readers.index(cls)
        claims = [r.__name__ for r in io.readers[:position + 1]
                  if extension in [e.lower() for e in r.file_extensions()]]
        assert claims == [name], f".{extension}: claimed by {claims} in detection order"


FAST_FILES = sorted(p for p in DATA.iterdir()
                    if p.suffix.lstrip(".").lower() in instrument_readers.READER_BY_EXTENSION)


@pytest.mark.parametrize("path", FAST_FILES, ids=lambda p: p.name)
def test_the_fast_path_reads_a_file_as_detection_does(path, monkeypatch):
    fast = instruments.read_instrument(path)
    monkeypatch.setattr(instruments, "open_by_extension", lambda _: None)
    detected = instruments.read_instrument(path)
    np.testing.assert_array_equal(fast.z, detected.z)
    assert fast.spacing == detected.spacing
    assert dict(fast.meta) == dict(detected.meta)


def test_a_file_its_reader_does_not_open_falls_back_to_detection(tmp_path):
    bad = tmp_path / "garbage.opd"
    bad.write_bytes(b"not an opd file at all" * 10)
    assert instrument_readers.open_by_extension(bad) is None
    with pytest.raises(instruments.MalformedFileError, match="garbage.opd"):
        instruments.read_instrument(bad)


def _run(code):
    return subprocess.run([sys.executable, "-c", code], cwd=ROOT, capture_output=True,
                          text=True, check=True, env={"PYTHONPATH": str(ROOT)}).stdout


def test_reading_an_opd_imports_one_reader_and_the_package_still_works_after():
    out = _run(
        "import sys\n"
        "from roughgp.io.instruments import read_instrument\n"
        "read_instrument('data/opd-1.opd')\n"
        "print('pandas' in sys.modules, 'scipy.signal' in sys.modules,"
        " 'SurfaceTopography.IO.SUR' in sys.modules, 'scipy.optimize' in sys.modules)\n"
        "import SurfaceTopography\n"
        "from SurfaceTopography.IO import open_topography, readers\n"
        "print(SurfaceTopography.__version__ != '', len(readers) > 30,"
        " open_topography('data/opd-1.opd').format())\n"
        "import NuMPI, NuMPI.MPIStub\n"
        "print(NuMPI.__version__ != '', NuMPI.MPI is NuMPI.MPIStub,"
        " hasattr(NuMPI.Optimization, 'l_bfgs'))\n")
    first, second, third = out.splitlines()
    # neither the other readers nor their dependencies, nor NuMPI's scipy.optimize
    assert first == "False False False False"
    assert second == "True True opd"
    assert third == "True True True"  # the deferred NuMPI is the whole package once asked


def _hfm(path, flags, heights_mm=None):
    """An HFM profile (x and height in mm, a validity flag per row), as its instruments write
    it (``X;Y;valid``, CRLF)."""
    n = len(flags)
    heights_mm = 106.6 + 1e-5 * np.sin(np.arange(n) / 9.0) if heights_mm is None else heights_mm
    rows = [f"{8.6722 + 0.0005 * i:.6f};{h:.6f};{f}" for i, (h, f) in
            enumerate(zip(heights_mm, flags))]
    path.write_bytes(("X;Y;valid\r\n[mm];[mm];[1/0]\r\n" + "\r\n".join(rows) + "\r\n").encode())
    return path


def test_an_hfm_file_s_unmeasured_rows_are_read_as_unmeasured(tmp_path):
    """SurfaceTopography reads an HFM file's first two columns only: a row flagged 0 (not
    measured), whose height is a placeholder (0 mm here, 106 mm below the others), was read as
    a measured height (Rv of about 100 mm on hfm-1.hfm with 100 such rows)."""
    flags = np.ones(400, dtype=int)
    flags[100:140] = 0
    heights = 106.6 + 1e-5 * np.sin(np.arange(400) / 9.0)
    heights[100:140] = 0.0
    z = instruments.read_instrument(_hfm(tmp_path / "p.hfm", flags, heights)).z
    assert z.shape == (400,)
    assert np.isnan(z[100:140]).all() and np.isfinite(np.delete(z, np.s_[100:140])).all()
    assert np.nanmax(z) - np.nanmin(z) < 0.1  # um: no placeholder left
    whole = instruments.read_instrument(_hfm(tmp_path / "q.hfm", np.ones(400, dtype=int))).z
    assert np.isfinite(whole).all()


def test_an_hfm_validity_column_with_other_values_is_refused(tmp_path):
    flags = np.ones(50, dtype=int)
    flags[7] = 2
    with pytest.raises(instruments.MalformedFileError, match="'valid' column must hold 1"):
        instruments.read_instrument(_hfm(tmp_path / "p.hfm", flags))
