"""The open real files of ``data/`` (``roughgp.experiments.real_maps``): each read right, the
crops equal to their originals, and the misreadings and silent garbage of issue 32 fixed."""

import os
import struct
import warnings
from pathlib import Path

import numpy as np
import pytest

from roughgp.experiments.real_maps import DATA, REAL_MAPS, REAL_PROFILES, real_file
from roughgp.io import measurement, plausibility
from roughgp.io.measurement import read_measurement
from roughgp.io.readers import MalformedFileError

MORE = Path("/work/shared/data/more")  # the originals of the crops, where at hand


def _unit(text):
    return {"µm": "um", "μm": "um"}.get(text, text)


def test_data_holds_at_least_12_maps_from_several_kinds_of_instrument():
    assert len(REAL_MAPS) >= 12
    techniques = {m.technique for m in REAL_MAPS} - {"unstated"}
    assert {"AFM", "confocal", "white-light interferometer", "focus variation"} <= techniques
    assert "stylus" in {p.technique for p in REAL_PROFILES}
    listed = {f.name for f in REAL_MAPS + REAL_PROFILES}
    on_disk = {p.name for p in DATA.iterdir() if p.suffix not in (".md", ".txt")
               or p.name in ("matrix-3.txt", "xy-4.txt", "xy-2.txt")}
    assert listed <= on_disk
    assert on_disk - listed == {"csv-2.csv", "xy-2.txt"}  # reader tests, not measurements
    with pytest.raises(ValueError, match="name must be one of"):
        real_file("nope.sur")


@pytest.mark.parametrize("entry", REAL_MAPS + REAL_PROFILES, ids=lambda e: e.name)
def test_every_listed_file_reads_in_its_stated_unit(entry):
    m = read_measurement(entry.path)
    assert m.kind == ("surface" if entry in REAL_MAPS else "profile")
    assert _unit(m.unit_source.split(" ")[0]) == _unit(entry.unit)
    assert max(m.z.shape) <= (10001 if m.kind == "profile" else 918)
    assert np.isfinite(m.z).mean() > 0.5
    if entry.source != "original":
        assert m.z.shape == (entry.window[2],) * 2
        assert entry.path.stat().st_size < 600 * 1024


@pytest.mark.parametrize("entry", [m for m in REAL_MAPS if m.window], ids=lambda e: e.name)
def test_a_crop_equals_its_window_of_the_original(entry):
    original = MORE / entry.source
    if not original.exists():
        pytest.skip(f"the original {original} is not at hand")
    whole = read_measurement(original)
    crop = read_measurement(entry.path)
    y0, x0, n = entry.window
    window = whole.z[y0:y0 + n, x0:x0 + n]
    np.testing.assert_array_equal(np.isnan(crop.z), np.isnan(window))
    scale = np.nanmax(np.abs(window))
    np.testing.assert_allclose(crop.z, window, rtol=0, atol=2e-16 * scale)
    assert crop.spacing == whole.spacing


def test_nms_spacing_is_read_from_its_header_in_nm_as_surfalize_reads_it():
    surfalize = pytest.importorskip("surfalize")
    path = DATA / "nms-1.nms"
    m = read_measurement(path)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        surface = surfalize.Surface.load(path)  # steps in um
    assert m.spacing == pytest.approx((surface.step_y, surface.step_x), rel=1e-12)
    assert m.spacing == pytest.approx((0.3125, 0.3125), rel=1e-6)  # a 160 um field
    assert m.unit_source == "µm (from the file)"  # no conversion to speak of
    raw = path.read_bytes()[1376:1392]
    assert struct.unpack("<2d", raw) == pytest.approx((312.5, 312.5), rel=1e-6)  # nm
    # SurfaceTopography reads the same bytes as mm: a 160 m field, which the check refuses
    with pytest.raises(MalformedFileError, match="implausible reading: 512 points"):
        plausibility.check_reading(m.z, (312500.0, 312500.0), path)


def test_gwyddion_matrix_header_gives_the_spacing_and_the_height_unit():
    from SurfaceTopography import read_topography
    m = read_measurement(DATA / "matrix-3.txt")
    assert m.spacing == pytest.approx((10.0 / 256, 10.0 / 256), rel=1e-12)  # Width: 10.00 µm
    assert m.unit_source.startswith("m (from the header")
    first = float((DATA / "matrix-3.txt").read_text(encoding="utf-8").splitlines()[4]
                  .split()[0])
    assert m.z[0, 0] == pytest.approx(first * 1e6, rel=1e-12)  # Value units: m
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        t = read_topography(str(DATA / "matrix-3.txt"))
    assert t.unit == "m"  # SurfaceTopography reads the header too, in metres
    assert np.asarray(t.pixel_size) * 1e6 == pytest.approx(m.spacing, rel=1e-9)
    np.testing.assert_allclose(m.z, t.heights().T * 1e6, rtol=1e-9)


def test_gwyddion_matrix_header_with_a_unit_roughgp_lacks_is_refused(tmp_path):
    path = tmp_path / "m.txt"
    path.write_text("# Width: 10.00 µm\n# Height: 10.00 µm\n# Value units: furlong\n"
                    "1 2\n3 4\n", encoding="utf-8")
    with pytest.raises(MalformedFileError, match="Value units.*'furlong'"):
        read_measurement(path)


def test_utf16_csv_with_an_index_column_and_a_um_header():
    m = read_measurement(DATA / "csv-2.csv")
    assert m.kind == "profile" and m.z.shape == (8,)
    assert m.unit_source == "um (from the column header)"
    assert m.spacing == pytest.approx((0.0833333333,), rel=1e-6)
    assert m.z == pytest.approx(np.full(8, -1.427432857434913))
    assert any("index" in note for note in m.notes)


def test_xy2_count_line_and_unit_line_are_read_and_its_irregular_x_refused_plainly():
    with pytest.raises(MalformedFileError, match="xy-2.txt: the x column is not a regular "
                                                 "grid.*--spacing"):
        read_measurement(DATA / "xy-2.txt")
    m = read_measurement(DATA / "xy-2.txt", spacing=1.5)
    assert m.z.shape == (24,) and m.unit_source == "um (from the column header)"
    assert m.z[0] == pytest.approx(17.85497)
    assert any("a count line" in note for note in m.notes)


def test_hfm_profile_is_in_mm_for_both_columns():
    m = read_measurement(DATA / "hfm-1.hfm")
    lines = (DATA / "hfm-1.hfm").read_text().splitlines()
    assert lines[1] == "[mm];[mm];[1/0]"
    x0, z0 = (float(v) for v in lines[2].split(";")[:2])
    x1 = float(lines[3].split(";")[0])
    assert m.spacing == pytest.approx(((x1 - x0) * 1e3,), rel=1e-6)  # 0.5 um
    assert m.z[0] == pytest.approx(z0 * 1e3, rel=1e-12)  # 106.6 mm, an absolute level


@pytest.mark.parametrize("spacing", [1e-300, 1e300, 0.0, float("inf")])
def test_a_spacing_beyond_the_bounds_is_refused_before_reading(tmp_path, spacing):
    np.save(tmp_path / "h.npy", np.zeros((4, 4)))
    with pytest.raises(ValueError, match=r"spacing must be from 1e-06 to 1e\+06 um"):
        read_measurement(tmp_path / "h.npy", spacing=spacing)


def test_unit_applies_to_npy_and_text_and_is_refused_for_x3p(tmp_path):
    z = np.arange(12.0).reshape(3, 4)
    np.save(tmp_path / "h.npy", z)
    m = read_measurement(tmp_path / "h.npy", unit="mm")
    np.testing.assert_allclose(m.z, z * 1e3)
    assert m.unit_source.startswith("mm (as given)")
    (tmp_path / "p.csv").write_text("".join(f"{v}\n" for v in range(5)))
    assert read_measurement(tmp_path / "p.csv", unit="nm").z[1] == pytest.approx(1e-3)
    with pytest.raises(ValueError, match="unit must be one of"):
        read_measurement(tmp_path / "h.npy", unit="furlong")
    with pytest.raises(ValueError, match="unit: an .x3p file stores metres"):
        read_measurement(DATA / "frt-1-crop.x3p", unit="mm")


# ------------------------------------------------------------------ silent garbage refused

def test_opd_with_one_changed_data_byte_is_refused_with_the_height_named(tmp_path):
    raw = bytearray((DATA / "opd-1.opd").read_bytes())
    raw[1000005] = 0x70  # the exponent byte of a float32 height: 3.6e26 mm
    bad = tmp_path / "changed.opd"
    bad.write_bytes(bytes(raw))
    with pytest.raises(MalformedFileError, match=r"implausible reading: the height z\[\d+, \d+\]"
                                                 r" = .* um \(.* m\), beyond the 1 m"):
        read_measurement(bad)


def test_sur_with_a_z_scale_of_1e30_is_refused(tmp_path):
    raw = bytearray((DATA / "sur-2.sur").read_bytes())
    assert struct.unpack("<f", raw[128:132])[0] == pytest.approx(1e-7)  # its z scale
    raw[128:132] = struct.pack("<f", 1e30)
    bad = tmp_path / "scaled.sur"
    bad.write_bytes(bytes(raw))
    with pytest.raises(MalformedFileError, match="implausible reading: the height"):
        read_measurement(bad)


@pytest.mark.parametrize("spacing, z, match", [
    ((float("nan"), 1.0), np.zeros((2, 2)), "a y step of nan um"),
    ((1.0, 0.0), np.zeros((2, 2)), "an x step of 0.0 um"),
    ((1.0, 2e6), np.zeros((2, 2)), "an x step of 2000000.0 um"),
    ((3125.0,), np.zeros(512), r"512 points at an x step of 3125 um make a field 1.6e\+06"),
    ((1.0, 1.0), np.full((2, 2), np.nan), "holds no measured point"),
    ((1.0, 1.0), np.array([[0.0, 2e6], [np.nan, 1.0]]), r"z\[0, 1\] = 2e\+06 um \(2 m\)"),
])
def test_the_plausibility_check_refuses_and_names_the_value(spacing, z, match):
    with pytest.raises(MalformedFileError, match="f.sur: .*" + match):
        plausibility.check_reading(z, spacing, "f.sur")


def test_the_plausibility_check_passes_every_real_file():
    # calibration: the bounds are far from every real reading (a check that can say no,
    # above, and says yes here)
    for entry in REAL_MAPS + REAL_PROFILES:
        m = read_measurement(entry.path)
        assert np.nanmax(np.abs(m.z)) < 0.2 * plausibility.BOUNDS["height"]
        assert min(m.spacing) > 50 * plausibility.BOUNDS["step"][0]
        assert max(s * n for s, n in zip(m.spacing, m.z.shape)) < 0.1 * plausibility.BOUNDS[
            "field"]


# ------------------------------------------------------------------ clear messages

def test_empty_file_says_it_is_empty(tmp_path):
    for name in ("e.sur", "e.csv", "e.x3p", "e.npy"):
        (tmp_path / name).write_bytes(b"")
        with pytest.raises(MalformedFileError, match=f"{name}: the file is empty"):
            read_measurement(tmp_path / name)


def test_unreadable_file_says_permission_not_format(tmp_path, monkeypatch):
    path = tmp_path / "locked.sur"
    path.write_bytes((DATA / "sur-2.sur").read_bytes()[:100])

    def refuse(*args, **kwargs):
        raise PermissionError(13, "Permission denied", str(path))

    monkeypatch.setattr(measurement, "open", refuse, raising=False)
    with pytest.raises(PermissionError, match="permission denied: the file exists but cannot "
                                              "be read"):
        read_measurement(path)


@pytest.mark.skipif(os.geteuid() == 0, reason="root reads any file")
def test_unreadable_file_by_its_mode(tmp_path):
    path = tmp_path / "locked.sur"
    path.write_bytes(b"x")
    path.chmod(0)
    with pytest.raises(PermissionError, match="permission denied"):
        read_measurement(path)


def test_bit_flipped_opd_header_is_refused_not_a_traceback(tmp_path):
    # byte 98 of opd-1.opd: SurfaceTopography then returns no pixel size, and roughgp read
    # it outside its try ("TypeError: 'NoneType' object is not iterable", a traceback)
    raw = bytearray((DATA / "opd-1.opd").read_bytes())
    raw[98] ^= 0xFF
    bad = tmp_path / "flipped.opd"
    bad.write_bytes(bytes(raw))
    with pytest.raises(MalformedFileError, match="flipped.opd: cannot be read: "
                                                 "SurfaceTopography's reader .* failed on its "
                                                 "content .* damaged or truncated") as error:
        read_measurement(bad)
    assert len(str(error.value)) < 400


def test_truncated_di_says_it_holds_no_channel(tmp_path):
    bad = tmp_path / "short.di"
    bad.write_bytes((DATA / "di-1.di").read_bytes()[:100])
    with pytest.raises(MalformedFileError, match="holds no data channel.*truncated or damaged"):
        read_measurement(bad)


def test_garbage_with_an_instrument_extension_says_what_is_wrong(tmp_path):
    bad = tmp_path / "noise.frt"
    bad.write_bytes(np.random.default_rng(0).bytes(5000))
    with pytest.raises(MalformedFileError, match="(not readable as FRT MicroProf|cannot be "
                                                 "read: the file states no lateral size)"):
        read_measurement(bad)
    cut = tmp_path / "cut.frt"
    cut.write_bytes((DATA / "frt-2.frt").read_bytes()[:100])
    with pytest.raises(MalformedFileError, match="cut.frt: not readable as FRT MicroProf.*"
                                                 "truncated or damaged"):
        read_measurement(cut)
    for name in ("zeros.opd", "text.sur"):
        (tmp_path / name).write_bytes(b"\0" * 64 if name.startswith("zeros") else b"hello\n")
        with pytest.raises(MalformedFileError) as error:
            read_measurement(tmp_path / name)
        assert "physical_sizes" not in str(error.value)
