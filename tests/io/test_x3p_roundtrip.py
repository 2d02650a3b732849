"""x3p round trips between roughgp and the two open Python tools that read x3p (issue 21):
SurfaceTopography (a runtime dependency) and surfalize (a test-only dependency, GPL-3).

roughgp writes -> the tool reads, and the tool writes -> roughgp reads: same shape, the same
orientation (a non-square ramp whose x and y slopes differ, so a transposed or flipped read
fails), the same spacing (dy != dx) and heights. Written files keep the input's offsets,
creator and comment, and say in their comment what roughgp did.
"""

from __future__ import annotations

import zipfile

import numpy as np
import pytest

from roughgp.cli.main import main
from roughgp.io import writers, x3p
from roughgp.io.measurement import read_measurement

NY, NX = 5, 8            # non-square
DY, DX = 1.5, 0.25       # um, dy != dx


def _ramp():
    """z[iy, ix] = 10 iy + ix (um) + a small curvature: every point distinct."""
    iy, ix = np.mgrid[0:NY, 0:NX]
    return 10.0 * iy + ix + 0.01 * ix ** 2 - 3.0


def _surfalize():
    try:
        import surfalize
    except ImportError:  # pragma: no cover - surfalize==0.19.2 is pinned in requirements.lock
        pytest.skip("surfalize is not installed (test-only dependency: pip install "
                    "surfalize==0.19.2, as in requirements.lock)")
    return surfalize


def _roughgp_file(tmp_path, name="rg.x3p", **meta):
    path = tmp_path / name
    x3p.write_x3p(path, _ramp(), (DY, DX), **meta)
    return path


def test_revision_is_the_one_every_reader_accepts(tmp_path):
    with zipfile.ZipFile(_roughgp_file(tmp_path)) as archive:
        xml = archive.read("main.xml").decode()
        names = archive.namelist()
    assert f"<Revision>{x3p.WRITE_REVISION}</Revision>" in xml
    assert x3p.WRITE_REVISION == "ISO5436 - 2000"
    assert "md5checksum.hex" in names and "<MD5ChecksumPointData>" in xml
    assert "<Increment>2.5e-07</Increment>" in xml and "<Increment>1.5e-06</Increment>" in xml


def test_surfacetopography_reads_what_roughgp_writes(tmp_path):
    from SurfaceTopography import read_topography
    topography = read_topography(str(_roughgp_file(tmp_path)))
    assert topography.unit == "m"
    assert topography.nb_grid_pts == (NX, NY)                 # SurfaceTopography: [ix, iy]
    np.testing.assert_allclose(np.asarray(topography.physical_sizes),
                               (NX * DX * 1e-6, NY * DY * 1e-6), rtol=1e-12)
    np.testing.assert_allclose(topography.heights().T * 1e6, _ramp(), rtol=1e-12, atol=1e-12)


def test_surfalize_reads_what_roughgp_writes(tmp_path):
    with pytest.warns(UserWarning, match="pixel size"):       # surfalize's note on dy != dx
        surface = _surfalize().Surface.load(_roughgp_file(tmp_path))
    assert surface.data.shape == (NY, NX)                     # surfalize: [iy, ix], um
    assert surface.step_x == pytest.approx(DX) and surface.step_y == pytest.approx(DY)
    np.testing.assert_allclose(surface.data, _ramp(), rtol=1e-12, atol=1e-12)


def test_x3pio_reads_what_roughgp_writes(tmp_path):
    import x3pio
    file = x3pio.read(_roughgp_file(tmp_path))
    assert file.revision.value == x3p.WRITE_REVISION
    np.testing.assert_allclose(file.layers[0].z * 1e6, _ramp(), rtol=1e-12, atol=1e-12)


def test_roughgp_reads_what_surfacetopography_writes(tmp_path):
    from SurfaceTopography import Topography
    path = tmp_path / "st.x3p"
    # SurfaceTopography holds heights [ix, iy]; physical sizes (sx, sy), here in um
    topography = Topography(_ramp().T.copy(), (NX * DX, NY * DY), unit="um")
    topography.to_x3p(str(path))
    for reading in (x3p.read_x3p(path), read_measurement(path)):
        assert reading.z.shape == (NY, NX)
        np.testing.assert_allclose(reading.spacing, (DY, DX), rtol=1e-12)
        np.testing.assert_allclose(reading.z, _ramp(), rtol=1e-12, atol=1e-12)


def test_surfacetopography_file_with_damaged_data_is_refused(tmp_path):
    """SurfaceTopography's md5checksum.hex holds the data's MD5 (not main.xml's): roughgp checks
    it against the member it names, so a damaged file is still refused."""
    from SurfaceTopography import Topography
    good = tmp_path / "st.x3p"
    Topography(_ramp().T.copy(), (NX * DX, NY * DY), unit="um").to_x3p(str(good))
    with zipfile.ZipFile(good) as archive:
        members = {name: archive.read(name) for name in archive.namelist()}
    data = bytearray(members["bindata/data.bin"])
    data[3] ^= 0xFF
    members["bindata/data.bin"] = bytes(data)
    bad = tmp_path / "damaged.x3p"
    with zipfile.ZipFile(bad, "w") as archive:
        for name, content in members.items():
            archive.writestr(name, content)
    with pytest.raises(x3p.MalformedFileError, match="checksum"):
        x3p.read_x3p(bad)


def test_roughgp_reads_what_surfalize_writes(tmp_path):
    surfalize = _surfalize()
    path = tmp_path / "sf.x3p"
    with pytest.warns(UserWarning, match="pixel size"):       # surfalize's own note on dy != dx
        surface = surfalize.Surface(_ramp(), DX, DY)
    surface.save(path)
    for reading in (x3p.read_x3p(path), read_measurement(path)):
        assert reading.z.shape == (NY, NX)
        np.testing.assert_allclose(reading.spacing, (DY, DX), rtol=1e-12)
        np.testing.assert_allclose(reading.z, _ramp(), rtol=1e-12, atol=1e-12)


def test_offsets_creator_and_comment_are_kept(tmp_path):
    from SurfaceTopography import read_topography
    path = _roughgp_file(tmp_path, offset=(1000.0, 2000.0, 3.0), creator="Lab A",
                         comment="a comment")
    reading = x3p.read_x3p(path)
    meta = reading.meta
    # x and y place the first point; the z offset is added to the heights (ISO 5436-2), as
    # SurfaceTopography adds it, so it is 0 in the offset written back
    np.testing.assert_allclose(meta["offset"], (1000.0, 2000.0, 0.0), rtol=1e-12)
    assert meta["z_offset"] == pytest.approx(3.0, rel=1e-12)
    assert meta["creator"] == "Lab A" and meta["comment"] == "a comment"
    topography = read_topography(str(path))
    np.testing.assert_allclose(topography.heights().T * 1e6, _ramp() + 3.0, rtol=1e-12)
    np.testing.assert_allclose(reading.z, topography.heights().T * 1e6, rtol=1e-12)


def test_write_heights_keeps_the_input_meta(tmp_path):
    source = {"offset": (5.0, 6.0, 0.5), "creator": "Lab B", "comment": "measured on Monday"}
    out = tmp_path / "o.x3p"
    writers.write_heights(out, _ramp(), (DY, DX), "roughgp fill in.x3p: filled", source=source)
    written = x3p.read_x3p(out)
    meta = written.meta
    assert meta["creator"] == "Lab B"
    assert meta["comment"] == "roughgp fill in.x3p: filled; the input's comment: measured on Monday"
    np.testing.assert_allclose(meta["offset"], (5.0, 6.0, 0.0), rtol=1e-12)
    np.testing.assert_allclose(written.z, _ramp() + 0.5, rtol=1e-12)  # the z offset, added
    csv = tmp_path / "o.csv"
    writers.write_heights(csv, _ramp(), DX, "roughgp fill in.x3p", source=source)
    text = csv.read_text()
    assert "# creator: Lab B" in text and "# offset_um: 5.0 6.0 0.5" in text
    assert "measured on Monday" in text
    np.testing.assert_allclose(read_measurement(csv).z, _ramp(), rtol=1e-11)


def test_fill_writes_back_the_input_meta_and_what_it_did(tmp_path, capsys):
    rng = np.random.default_rng(0)
    z = rng.normal(size=(24, 32))
    z[5, 7] = z[10, 20] = np.nan
    source = tmp_path / "holes.x3p"
    x3p.write_x3p(source, z, 1.0, offset=(10.0, 20.0, 1.0), creator="Lab C", comment="raw")
    out = tmp_path / "filled.x3p"
    sd = tmp_path / "sd.x3p"
    code = main(["fill", str(source), "--out", str(out), "--sd", str(sd), "--samples", "2",
                 "--block", "8", "--blocks", "4"])
    assert code == 0, capsys.readouterr().err
    meta = x3p.read_x3p(out).meta
    assert meta["creator"] == "Lab C"
    assert meta["comment"].startswith("roughgp fill holes.x3p --seed 0: the form")
    assert "2 missing points filled by the GP posterior mean" in meta["comment"]
    assert meta["comment"].endswith("the input's comment: raw")
    # the input's z offset (1 um) is in the heights read, so written back once, not twice
    np.testing.assert_allclose(meta["offset"], (10.0, 20.0, 0.0), rtol=1e-12, atol=1e-12)
    filled = x3p.read_x3p(out).z
    measured = np.isfinite(z)
    np.testing.assert_allclose(filled[measured], z[measured] + 1.0, rtol=1e-9, atol=1e-9)
    sd_meta = x3p.read_x3p(sd).meta
    assert "posterior sd" in sd_meta["comment"]
    np.testing.assert_allclose(sd_meta["offset"], (10.0, 20.0, 0.0), rtol=1e-12, atol=1e-12)


def test_integer_heights_with_a_z_offset_read_as_surfacetopography_reads_them(tmp_path):
    # as openGPS's ISO5436-sample4_bin.x3p: int16 heights, a z increment and a z offset of
    # -0.5 m; SurfaceTopography reads z = raw * increment + offset, and so does roughgp
    import x3pio
    from SurfaceTopography import read_topography
    heights = 0.486 + 1e-6 * _ramp()  # metres: about 0.486 m, as that sample's z[0, 0]
    path = tmp_path / "int16-offset.x3p"
    x3pio.write(path, heights, x_scale=DX * 1e-6, y_scale=DY * 1e-6,
                z_type=x3pio.DataType.INT16,
                placement=x3pio.Placement(offset=(0.0, 0.0, -0.5)),
                coordinate_system=x3pio.CoordinateSystem.GLOBAL,
                revision=x3pio.Revision(x3p.WRITE_REVISION))
    info = x3pio.info(path)
    assert info.header.z.data_type.name == "INT16" and info.placement.offset[2] == -0.5
    reading = read_measurement(path)
    theirs = read_topography(str(path)).heights().T * 1e6
    np.testing.assert_allclose(reading.z, theirs, rtol=1e-12)
    step = info.header.z.increment * 1e6  # um: 0.986 m stored in int16 steps
    np.testing.assert_allclose(reading.z, heights * 1e6, rtol=0, atol=0.51 * step)
    # without the offset the heights would read 0.986 m (the 986 000 against 486 000)
    assert reading.meta["z_offset"] == pytest.approx(-5e5)
    assert reading.z[0, 0] == pytest.approx(486000.0, abs=step)


def _patched_member(tmp_path, name, *, flag=None, method=None):
    """A copy of a roughgp x3p whose bindata/data.bin entry claims an encryption flag or an
    unknown compression method (in its local and its central header)."""
    raw = bytearray(_roughgp_file(tmp_path).read_bytes())
    member = b"bindata/data.bin"
    for signature, flag_at, method_at, name_at in ((b"PK\x03\x04", 6, 8, 30),
                                                   (b"PK\x01\x02", 8, 10, 46)):
        at = raw.find(signature)
        while raw[at + name_at:at + name_at + len(member)] != member:
            at = raw.find(signature, at + 4)
        if flag is not None:
            raw[at + flag_at] |= flag
        if method is not None:
            raw[at + method_at:at + method_at + 2] = method.to_bytes(2, "little")
    path = tmp_path / name
    path.write_bytes(bytes(raw))
    return path


def test_encrypted_or_unknown_compression_members_are_refused_plainly(tmp_path):
    encrypted = _patched_member(tmp_path, "encrypted.x3p", flag=0x1)
    with pytest.raises(x3p.MalformedFileError, match="encrypted.x3p: the zip member "
                                                     "'bindata/data.bin' is encrypted"):
        read_measurement(encrypted)
    packed = _patched_member(tmp_path, "packed.x3p", method=99)
    with pytest.raises(x3p.MalformedFileError, match="packed.x3p: .* compressed with method "
                                                     "99, which roughgp cannot decompress"):
        read_measurement(packed)
    for path in (encrypted, packed):  # what x3pio alone raises: RuntimeError, NotImplementedError
        import x3pio
        with pytest.raises((RuntimeError, NotImplementedError, x3pio.X3pError)):
            x3pio.read(path)


def test_a_spread_keeps_the_x_and_y_offsets_but_not_the_z_offset(tmp_path):
    source = {"offset": (5.0, 6.0, 0.5), "creator": "Lab B"}
    out = tmp_path / "sd.x3p"
    writers.write_heights(out, _ramp(), (DY, DX), "an sd", source=source, spread=True)
    np.testing.assert_allclose(x3p.read_x3p(out).meta["offset"], (5.0, 6.0, 0.0), rtol=1e-12)
