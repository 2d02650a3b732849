"""Real measurements (data/, written by instruments and other software) read with the right
shape, orientation, spacing and height unit; x3p from other writers; profiles with rounded x;
format detection by content; `roughgp texture` on them with the operators it applied."""

import hashlib
import json
import warnings
import zipfile
from pathlib import Path

import numpy as np
import pytest

from roughgp.cli.main import main
from roughgp.io import x3p
from roughgp.io.measurement import read_measurement
from roughgp.io.readers import MalformedFileError

DATA = Path(__file__).resolve().parents[2] / "data"


def _surface_topography(name):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        from SurfaceTopography import open_topography
        return open_topography(str(DATA / name)).topography()


@pytest.mark.parametrize("name, factor", [("sur-2.sur", 1e3), ("opd-1.opd", 1e3),
                                          ("di-1.di", 1e-3)])
def test_instrument_files_match_surface_topography_transposed(name, factor):
    m = read_measurement(DATA / name)
    t = _surface_topography(name)
    nx, ny = t.nb_grid_pts
    assert m.z.shape == (ny, nx) and nx != ny or name == "di-1.di"  # z[iy, ix]
    expected = np.ma.filled(np.ma.asarray(t.heights(), dtype=float), np.nan).T * factor
    np.testing.assert_array_equal(np.isnan(m.z), np.isnan(expected))
    np.testing.assert_allclose(m.z, expected, rtol=1e-12, equal_nan=True)
    np.testing.assert_allclose(m.spacing, np.asarray(t.pixel_size)[::-1] * factor, rtol=1e-12)
    assert t.unit in m.unit_source and "SurfaceTopography" in m.reader


def test_sur_file_header_states_its_grid():
    m = read_measurement(DATA / "sur-2.sur")
    raw = _surface_topography("sur-2.sur").info["raw_metadata"]
    assert m.z.shape == (raw["nb_grid_pts_y"], raw["nb_grid_pts_x"]) == (484, 563)
    assert m.spacing == pytest.approx((raw["grid_spacing_y"] * 1e3, raw["grid_spacing_x"] * 1e3))
    assert 0 < np.isnan(m.z).sum() < 1000  # "a few missing points"


def test_x3ptools_land_reads_with_its_top_folder_and_no_namespace():
    m = read_measurement(DATA / "sample-land.x3p")
    assert m.z.shape == (256, 918) and m.spacing == pytest.approx((2.58, 2.58))
    assert 0.10 < np.isnan(m.z).mean() < 0.12  # about 11 % missing
    assert "lenient" in m.reader and m.meta["creator"].startswith("CSAFE")
    with zipfile.ZipFile(DATA / "sample-land.x3p") as archive:
        data = np.frombuffer(archive.read("sample-land/bindata/data.bin"), dtype="<f8")
    raw = data.reshape(256, 918) * 1e6  # x runs fastest: row iy, column ix
    np.testing.assert_array_equal(np.isnan(m.z), ~np.isfinite(raw))
    np.testing.assert_allclose(m.z, raw, equal_nan=True)


def test_stylus_profile_with_rounded_x():
    m = read_measurement(DATA / "dektak-1.csv")
    assert m.z.shape == (9600,)
    assert m.spacing[0] == pytest.approx(0.156, abs=5e-4)  # the header's resolution
    assert m.spacing[0] * 9599 == pytest.approx(1499.8, abs=0.2)  # its last x
    assert "rounded" in m.spacing_source and "column header" in m.unit_source


def test_text_profile_printed_to_six_decimals():
    m = read_measurement(DATA / "xy-4.txt")
    t = _surface_topography("xy-4.txt")
    assert m.z.shape == (10001,)
    assert m.spacing[0] == pytest.approx(t.physical_sizes[0] / 10000, rel=1e-4)
    assert "assumed" in m.unit_source  # the file states no unit: said, not hidden


def test_rounded_x_is_accepted_within_its_digits_and_irregular_x_refused(tmp_path):
    x = np.arange(3000) / 3
    good = tmp_path / "thirds.csv"
    good.write_text("".join(f"{v:.6g},{np.sin(v):.6g}\n" for v in x))
    m = read_measurement(good)
    assert m.spacing[0] == pytest.approx(1 / 3, rel=1e-9)
    bad = tmp_path / "irregular.csv"
    xs = x.copy()
    xs[1500] += 0.01  # 30 times the rounding of '%.6g' there
    bad.write_text("".join(f"{v:.6g},{np.sin(v):.6g}\n" for v in xs))
    with pytest.raises(MalformedFileError, match="not a regular grid.*--spacing"):
        read_measurement(bad)


def _x3p_zip(path, *, dtype="I", folder="top/", namespace=False, scale=1e-8, offset=2e-6,
             valid=None, checksum=True, root="ISO5436_2"):
    z = (np.arange(12, dtype=np.int16).reshape(3, 4) - 5)
    data = z.astype({"I": "<i2", "L": "<i4", "F": "<f4", "D": "<f8"}[dtype]).tobytes()
    ns = ' xmlns:p="http://www.opengps.eu/2008/ISO5436_2"' if namespace else ""
    root = f"p:{root}" if namespace else root
    valid_link = "<ValidPointsLink>bindata/valid.bin</ValidPointsLink>" if valid is not None else ""
    md5 = f"<MD5ChecksumPointData>{hashlib.md5(data).hexdigest()}</MD5ChecksumPointData>" \
        if checksum else ""
    xml = (f"<?xml version='1.0'?><{root}{ns}><Record1><Revision>ISO5436 - 2000</Revision>"
           "<FeatureType>SUR</FeatureType><Axes>"
           "<CX><AxisType>I</AxisType><DataType>D</DataType><Increment>2e-06</Increment>"
           "<Offset>0</Offset></CX><CY><AxisType>I</AxisType><DataType>D</DataType>"
           "<Increment>5e-07</Increment><Offset>0</Offset></CY>"
           f"<CZ><AxisType>A</AxisType><DataType>{dtype}</DataType><Increment>{scale}"
           f"</Increment><Offset>{offset}</Offset></CZ></Axes></Record1>"
           "<Record2><Creator>someone else</Creator></Record2><Record3><MatrixDimension>"
           "<SizeX>4</SizeX><SizeY>3</SizeY><SizeZ>1</SizeZ></MatrixDimension><DataLink>"
           f"<PointDataLink>bindata/data.bin</PointDataLink>{md5}{valid_link}</DataLink>"
           f"</Record3></{root}>").encode()
    with zipfile.ZipFile(path, "w") as archive:
        archive.writestr(folder + "main.xml", xml)
        archive.writestr(folder + "md5checksum.hex", f"{hashlib.md5(xml).hexdigest()} *main.xml")
        archive.writestr(folder + "bindata/data.bin", data)
        if valid is not None:
            archive.writestr(folder + "bindata/valid.bin",
                             np.packbits(valid.ravel(), bitorder="little").tobytes())
    return z


@pytest.mark.parametrize("root", ["ISO5436_2", "ISO5436"])
@pytest.mark.parametrize("dtype", ["I", "L", "F", "D"])
def test_x3p_from_another_writer_with_integer_or_float_data(tmp_path, dtype, root):
    path = tmp_path / f"other-{dtype}.x3p"
    raw = _x3p_zip(path, dtype=dtype, root=root)
    h = x3p.read_x3p(path)
    # x3pio reads the first; the root element of x3ptools' files needs the lenient reader
    assert ("lenient" in h.meta.get("reader", "")) == (root == "ISO5436")
    # CZ increment 1e-8 m, CZ offset 2e-6 m: z = raw * increment + offset (ISO 5436-2)
    np.testing.assert_allclose(h.z, raw * 1e-8 * 1e6 + 2.0, rtol=1e-6)
    assert h.z.shape == (3, 4) and h.spacing == pytest.approx((0.5, 2.0))
    assert h.meta["z_offset"] == pytest.approx(2.0) and h.meta["offset"][2] == 0.0


def test_x3p_valid_points_mask_and_damaged_data(tmp_path):
    valid = np.ones((3, 4), dtype=bool)
    valid[1, 2] = False
    for root in ("ISO5436_2", "ISO5436"):  # x3pio's reader and the lenient one
        path = tmp_path / f"masked-{root}.x3p"
        _x3p_zip(path, valid=valid, root=root)
        h = x3p.read_x3p(path)
        assert np.isnan(h.z[1, 2]) and np.isfinite(np.delete(h.z.ravel(), 6)).all()
    for root in ("ISO5436_2", "ISO5436"):  # the data no longer match their MD5 checksum
        damaged = tmp_path / f"damaged-{root}.x3p"
        _x3p_zip(damaged, root=root)
        with zipfile.ZipFile(damaged) as archive:
            members = {n: archive.read(n) for n in archive.namelist()}
        members["top/bindata/data.bin"] = b"\x00" * 24
        with zipfile.ZipFile(damaged, "w") as archive:
            for name, content in members.items():
                archive.writestr(name, content)
        with pytest.raises(MalformedFileError, match="checksum"):
            x3p.read_x3p(damaged)


def test_format_detection_by_content(tmp_path):
    text_dat = tmp_path / "heights.dat"
    text_dat.write_text("1 2 3 4\n5 6 7 8\n9 10 11 12\n")   # (3 columns: ambiguous, refused)
    assert read_measurement(text_dat).reader == "roughgp text grid"
    binary_txt = tmp_path / "binary.txt"
    binary_txt.write_bytes(b"\x00\x01\x02garbage" * 100)
    with pytest.raises(MalformedFileError, match="SurfaceTopography"):
        read_measurement(binary_txt)
    sur_named_dat = tmp_path / "renamed.dat"
    sur_named_dat.write_bytes((DATA / "sur-2.sur").read_bytes())
    assert read_measurement(sur_named_dat).z.shape == (484, 563)


def _texture(capsys, *args):
    code = main(["texture", *map(str, args)])
    out, err = capsys.readouterr()
    assert code == 0, err
    return out


@pytest.mark.parametrize("name", ["dektak-1.csv", "xy-4.txt", "sur-2.sur", "opd-1.opd",
                                  "di-1.di", "sample-land.x3p"])
def test_texture_prints_the_operators_for_each_file(capsys, tmp_path, name):
    out = _texture(capsys, DATA / name, "--json", tmp_path / "t.json")
    assert "operators: F:" in out
    record = json.loads((tmp_path / "t.json").read_text())
    assert record["operators"][0].startswith("F:")
    key = "Sq" if record["kind"] == "surface" else "Rq"
    assert record["parameters"][key] > 0


def test_texture_unfiltered_and_explicit_cutoffs(capsys, tmp_path):
    out = _texture(capsys, DATA / "sur-2.sur", "--unfiltered")
    assert "operators: none" in out
    out = _texture(capsys, DATA / "sur-2.sur", "--s-filter", "none", "--l-filter", "80")
    assert "L: Gaussian 80 um" in out and "S: Gaussian" not in out
    code = main(["texture", str(DATA / "sur-2.sur"), "--l-filter", "-3"])
    assert code == 2 and "nesting index must be > 0" in capsys.readouterr().err


def test_texture_help_lists_the_instrument_formats(capsys):
    assert main(["texture", "--help"]) == 0
    out = capsys.readouterr().out
    for fmt in (".sur", ".opd", ".di", ".plu", ".datx", ".mnt", ".nms", ".vk4", ".sdf", ".x3p"):
        assert fmt in out
    from roughgp.io.instruments import instrument_formats
    formats = {f for f, _ in instrument_formats()}
    assert {"sur", "opd", "di", "plu", "datx", "mnt", "nms", "sdf"} <= formats
