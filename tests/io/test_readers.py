"""Tests of roughgp.io.readers (text / CSV / xyz / x3p) and roughgp.metrology.levelling.

Round trips use non-square arrays whose rows and columns differ (z = 10 * iy + ix + ...), so
a transposed or flipped read cannot pass. Hostile x3p files are built from a valid one by
rewriting members of its zip; unless a test is about the checksum, the MD5 of main.xml is
recomputed so that the check under test is the one that fires.
"""

from __future__ import annotations

import dataclasses
import hashlib
import io
import re
import zipfile

import numpy as np
import pytest

from roughgp.io import readers, x3p
from roughgp.io.readers import MalformedFileError
from roughgp.metrology.levelling import LevelFit, level


def _grid(ny=3, nx=5):
    iy, ix = np.mgrid[0:ny, 0:nx]
    return 10.0 * iy + ix + 0.125


def _write(path, text):
    path.write_text(text)
    return path


def _raises(path, *patterns):
    """pytest.raises for a MalformedFileError whose message names ``path`` and matches."""
    class _Ctx:
        def __enter__(self):
            self.ctx = pytest.raises(MalformedFileError)
            self.info = self.ctx.__enter__()
            return self.info

        def __exit__(self, *exc):
            suppressed = self.ctx.__exit__(*exc)
            message = str(self.info.value)
            assert str(path) in message, message
            for pattern in patterns:
                assert re.search(pattern, message), (pattern, message)
            return suppressed
    return _Ctx()


# --------------------------------------------------------------------------- profiles

def test_profile_round_trip_csv_with_header(tmp_path):
    x = np.arange(7) * 0.5
    z = np.sin(x) * 3.0
    z[2] = np.nan
    path = tmp_path / "p.csv"
    np.savetxt(path, np.column_stack([x, z]), delimiter=",", header="x (mm),z (um)",
               comments="")
    xr, zr = readers.read_profile(path)
    assert xr.dtype == zr.dtype == np.float64
    np.testing.assert_array_equal(xr, x)
    np.testing.assert_array_equal(zr, z)          # NaN in the same place
    xs, zs = readers.read_profile(path, unit_scale=(1000.0, 1.0))
    np.testing.assert_allclose(xs, x * 1000.0)
    np.testing.assert_array_equal(zs, z)


def test_profile_whitespace_comments_missing_tokens_and_columns(tmp_path):
    path = _write(tmp_path / "p.txt",
                  "# instrument export\nindex x z\n\n0 0.0 1.5\n1 0.1 NA\n"
                  "% a comment\n2 0.2 nan\n3 0.3 -2.5\n")
    x, z = readers.read_profile(path, x_column=1, z_column=2)
    np.testing.assert_allclose(x, [0.0, 0.1, 0.2, 0.3])
    np.testing.assert_array_equal(np.isnan(z), [False, True, True, False])
    _, zl = readers.read_profile(path, x_column=1, z_column=-1)
    np.testing.assert_array_equal(zl, z)


def test_profile_heights_only_with_spacing(tmp_path):
    path = _write(tmp_path / "h.txt", "height\n1\n2\n4\n")
    x, z = readers.read_profile(path, spacing=0.25)
    np.testing.assert_allclose(x, [0.0, 0.25, 0.5])
    np.testing.assert_allclose(z, [1.0, 2.0, 4.0])
    with _raises(path, "z_column=1", "1 column"):
        readers.read_profile(path)              # no x column and no spacing


def test_profile_explicit_delimiter_and_skiprows(tmp_path):
    path = _write(tmp_path / "p.csv", "12\n0;1\n1;\n2;3\n")     # empty field: missing height
    x, z = readers.read_profile(path, delimiter=";", skiprows=1)
    np.testing.assert_allclose(x, [0, 1, 2])
    assert np.isnan(z[1]) and z[2] == 3.0


@pytest.mark.parametrize("text, line, pattern", [
    ("x,z\n0,1\n2,1\n1,1\n", 4, "strictly increasing"),
    ("x,z\n0,1\n1,1\n1,2\n", 4, "strictly increasing"),
    ("x,z\n0,1\nnan,1\n2,1\n", 3, "finite"),
    ("x,z\n0,1\n1,1,7\n", 3, "3 values.*line 2"),
    ("x,z\n0,1\n1,1\nend of data\n", 4, "not a row of numbers"),
    ("0,1\n1,inf\n", 2, "infinite"),
])
def test_profile_bad_files_name_file_and_line(tmp_path, text, line, pattern):
    path = _write(tmp_path / "bad.csv", text)
    with _raises(path, f"line {line}", pattern):
        readers.read_profile(path)


def test_profile_bad_files_without_line(tmp_path):
    empty = _write(tmp_path / "empty.csv", "x,z\n# nothing\n")
    with _raises(empty, "no rows of numbers"):
        readers.read_profile(empty)
    single = _write(tmp_path / "one.csv", "0,1\n")
    with _raises(single, "at least 2 points"):
        readers.read_profile(single)
    path = _write(tmp_path / "p.csv", "0,1\n1,2\n")
    with _raises(path, "z_column=5"):
        readers.read_profile(path, z_column=5)
    strict = _write(tmp_path / "strict.csv", "x,z\n0,1\n1,2\n")
    with _raises(strict, "line 1"):
        readers.read_profile(strict, skiprows=0)    # the header is data when skiprows=0


@pytest.mark.parametrize("kwargs, name", [
    ({"skiprows": -1}, "skiprows"), ({"unit_scale": 0.0}, "unit_scale"),
    ({"delimiter": ""}, "delimiter"), ({"spacing": -1.0}, "spacing"),
    ({"x_column": 0.5}, "x_column"),
])
def test_profile_bad_parameters(tmp_path, kwargs, name):
    path = _write(tmp_path / "p.csv", "0,1\n1,2\n")
    with pytest.raises(ValueError, match=name):
        readers.read_profile(path, **kwargs)


# --------------------------------------------------------------------------- grids, xyz

def test_surface_round_trip_csv_grid(tmp_path):
    z = _grid()
    z[1, 3] = np.nan
    path = tmp_path / "g.csv"
    np.savetxt(path, z, delimiter=",", header="heights in um, rows = y", comments="")
    zr, spacing = readers.read_surface(path, spacing=(2.0, 0.5))
    assert zr.shape == (3, 5) and spacing == (2.0, 0.5)
    np.testing.assert_array_equal(zr, z)
    zt, sp = readers.read_surface(path, spacing=1.5, unit_scale=2.0)
    np.testing.assert_array_equal(zt, 2.0 * z)
    assert sp == (1.5, 1.5)


def test_surface_bad_files(tmp_path):
    ragged = _write(tmp_path / "ragged.txt", "1 2 3\n4 5 6\n7 8\n")
    with _raises(ragged, "line 3", "2 values"):
        readers.read_surface(ragged, spacing=1.0)
    infinite = _write(tmp_path / "inf.txt", "1 2\n3 -inf\n")
    with _raises(infinite, "line 2", "infinite"):
        readers.read_surface(infinite, spacing=1.0)
    with pytest.raises(ValueError, match="spacing"):
        readers.read_surface(ragged, spacing=(1.0, np.inf))


def _xyz_text(z, dy, dx, order, drop=(), fmt="{:.6f}"):
    ny, nx = z.shape
    rows = []
    for k in order:
        iy, ix = divmod(int(k), nx)
        if (iy, ix) in drop:
            continue
        rows.append(" ".join(fmt.format(v) for v in (ix * dx + 3.0, iy * dy - 1.0))
                    + f" {float(z[iy, ix])!r}")
    return "x y z\n" + "\n".join(rows) + "\n"


def test_xyz_round_trip_any_order_missing_and_nan(tmp_path):
    z = _grid(4, 6)
    z[0, 5] = np.nan
    order = np.random.default_rng(0).permutation(z.size)
    path = _write(tmp_path / "s.xyz", _xyz_text(z, 0.3, 0.1, order, drop={(2, 1)}))
    zr, (dy, dx) = readers.read_xyz(path)
    assert zr.shape == (4, 6)
    np.testing.assert_allclose((dy, dx), (0.3, 0.1), rtol=1e-9)
    expected = z.copy()
    expected[2, 1] = np.nan                                  # not listed: missing
    np.testing.assert_array_equal(zr, expected)


def test_xyz_bad_files(tmp_path):
    z = _grid(3, 4)
    order = np.arange(z.size)
    text = _xyz_text(z, 1.0, 1.0, order)
    twice = _write(tmp_path / "twice.xyz", text + "3.0 -1.0 5\n")
    with _raises(twice, "listed twice", f"line {z.size + 2}", "also on line 2"):
        readers.read_xyz(twice)
    off = _write(tmp_path / "off.xyz", text + "3.3 0.0 1\n")     # x = 3.3 off a step-1 grid
    with _raises(off, "regular grid", "line 14"):
        readers.read_xyz(off)
    nan_x = _write(tmp_path / "nanx.xyz", "0 0 1\nnan 1 2\n1 1 3\n")
    with _raises(nan_x, "line 2", "finite"):
        readers.read_xyz(nan_x)
    flat = _write(tmp_path / "flat.xyz", "0 5 1\n1 5 2\n2 5 3\n")
    with _raises(flat, "same y", "read_profile"):
        readers.read_xyz(flat)
    huge = _write(tmp_path / "huge.xyz", "0 0 1\n1e-6 0 1\n1e6 0 1\n0 1 1\n")
    with _raises(huge, "MAX_POINTS"):                          # refused before allocating
        readers.read_xyz(huge)


# --------------------------------------------------------------------------- x3p

def test_x3p_round_trip_surface_layout_units_and_nan(tmp_path):
    import x3pio
    z = _grid(3, 5) * 0.37
    z[2, 0] = np.nan
    path = tmp_path / "s.x3p"
    x3p.write_x3p(path, z, (2.0, 0.5), comment="round trip")
    h = x3p.read_x3p(path)
    assert isinstance(h, x3p.HeightMap) and h.unit == "um"
    assert h.z.shape == (3, 5) and h.z.dtype == np.float64
    np.testing.assert_allclose(h.z, z, rtol=1e-14, atol=0)
    assert np.isnan(h.z[2, 0]) and np.count_nonzero(np.isnan(h.z)) == 1
    np.testing.assert_allclose(h.spacing, (2.0, 0.5), rtol=1e-14)
    assert h.meta["feature_type"] == "surface" and h.meta["comment"] == "round trip"
    # the file itself: metres, SizeX = 5 columns along x, rows along y
    raw = x3pio.read(path)
    assert raw.header.x.increment == pytest.approx(0.5e-6)
    assert raw.header.y.increment == pytest.approx(2.0e-6)
    layer = raw.layers[0]
    assert layer.z.shape == (3, 5)
    np.testing.assert_allclose(layer.z[0, 1] - layer.z[0, 0], 0.37e-6)   # x step: +1
    np.testing.assert_allclose(layer.z[1, 0] - layer.z[0, 0], 3.7e-6)    # y step: +10
    with pytest.raises(dataclasses.FrozenInstanceError):
        h.unit = "mm"


def test_x3p_round_trip_profile(tmp_path):
    z = np.array([0.5, -1.25, np.nan, 3.0])
    path = tmp_path / "p.x3p"
    x3p.write_x3p(path, z, 0.1)
    h = x3p.read_x3p(path)
    assert h.z.shape == (4,) and h.meta["feature_type"] == "profile"
    np.testing.assert_allclose(h.z, z, rtol=1e-14)
    np.testing.assert_allclose(h.spacing, (0.1,), rtol=1e-14)


def test_write_x3p_bad_input(tmp_path):
    with pytest.raises(ValueError, match="infinite"):
        x3p.write_x3p(tmp_path / "a.x3p", [[1.0, np.inf]], 1.0)
    with pytest.raises(ValueError, match="spacing"):
        x3p.write_x3p(tmp_path / "a.x3p", [[1.0, 2.0]], (1.0, 0.0))
    with pytest.raises(ValueError, match="shape"):
        x3p.write_x3p(tmp_path / "a.x3p", np.zeros((2, 2, 2)), 1.0)


@pytest.fixture
def x3p_members(tmp_path):
    """The members of a valid 3 x 4 surface file, as {name: bytes}."""
    path = tmp_path / "valid.x3p"
    x3p.write_x3p(path, _grid(3, 4), (1.0, 1.0))
    with zipfile.ZipFile(path) as archive:
        return {name: archive.read(name) for name in archive.namelist()}


def _rezip(path, members, *, edit=None, fix_md5=True, drop=()):
    members = dict(members)
    if edit is not None:
        members["main.xml"] = edit(members["main.xml"].decode()).encode()
    if fix_md5:
        digest = hashlib.md5(members["main.xml"]).hexdigest()
        members["md5checksum.hex"] = f"{digest} *main.xml\n".encode()
    with zipfile.ZipFile(path, "w", compression=zipfile.ZIP_DEFLATED) as archive:
        for name, content in members.items():
            if name not in drop:
                archive.writestr(name, content)
    return path


def test_x3p_rewritten_valid_file_still_reads(tmp_path, x3p_members):
    path = _rezip(tmp_path / "ok.x3p", x3p_members)
    np.testing.assert_allclose(x3p.read_x3p(path).z, _grid(3, 4), rtol=1e-14)


def test_x3p_negative_increment_flips_to_increasing_positions(tmp_path, x3p_members):
    def negative_y(xml):
        return re.sub(r"(<CY>.*?<Increment>)([^<]*)", r"\1-1e-06", xml, flags=re.S)
    h = x3p.read_x3p(_rezip(tmp_path / "neg.x3p", x3p_members, edit=negative_y))
    np.testing.assert_allclose(h.z, _grid(3, 4)[::-1], rtol=1e-14)
    np.testing.assert_allclose(h.spacing, (1.0, 1.0))


def test_x3p_not_zip_bad_zip_no_main(tmp_path, x3p_members):
    text = _write(tmp_path / "text.x3p", "x,z\n0,1\n")
    with _raises(text, "not a .*zip"):
        x3p.read_x3p(text)
    good = _rezip(tmp_path / "good.x3p", x3p_members).read_bytes()
    truncated = tmp_path / "truncated.x3p"
    truncated.write_bytes(good[: len(good) // 2])
    with _raises(truncated, "zip"):
        x3p.read_x3p(truncated)
    no_main = _rezip(tmp_path / "nomain.x3p", x3p_members, fix_md5=False, drop=("main.xml",))
    with _raises(no_main, "no main.xml"):
        x3p.read_x3p(no_main)


def test_x3p_damaged_member(tmp_path, x3p_members):
    path = tmp_path / "crc.x3p"
    data = bytes(x3p_members["bindata/data.bin"])
    # store data.bin uncompressed, then flip one of its bytes: a CRC (or MD5) mismatch
    buffer = io.BytesIO()
    with zipfile.ZipFile(buffer, "w", compression=zipfile.ZIP_STORED) as archive:
        for name, content in x3p_members.items():
            archive.writestr(name, content)
    blob = bytearray(buffer.getvalue())
    at = blob.find(data) + 5
    blob[at] ^= 0xFF
    path.write_bytes(bytes(blob))
    with _raises(path, "CRC|checksum|MD5"):
        x3p.read_x3p(path)


def test_x3p_wrong_md5_checksum(tmp_path, x3p_members):
    members = dict(x3p_members)
    members["md5checksum.hex"] = b"0" * 32 + b" *main.xml\n"
    path = _rezip(tmp_path / "md5.x3p", members, fix_md5=False)
    with _raises(path, "MD5"):
        x3p.read_x3p(path)
    # main.xml changed after the checksum was written
    path = _rezip(tmp_path / "md5b.x3p", x3p_members, fix_md5=False,
                  edit=lambda xml: xml.replace("<Offset>0.0</Offset>", "<Offset>0.5</Offset>", 1))
    with _raises(path, "MD5"):
        x3p.read_x3p(path)


def _set_size(sx, sy):
    def edit(xml):
        xml = re.sub(r"<SizeX>\d+</SizeX>", f"<SizeX>{sx}</SizeX>", xml)
        return re.sub(r"<SizeY>\d+</SizeY>", f"<SizeY>{sy}</SizeY>", xml)
    return edit


def test_x3p_absurd_declared_size_is_refused_before_reading(tmp_path, x3p_members):
    path = _rezip(tmp_path / "huge.x3p", x3p_members, edit=_set_size(10 ** 6, 10 ** 6))
    with _raises(path, "MAX_POINTS", "1000000 x 1000000"):
        x3p.read_x3p(path)


def test_x3p_data_size_mismatch(tmp_path, x3p_members):
    path = _rezip(tmp_path / "size.x3p", x3p_members, edit=_set_size(5, 3))
    with _raises(path, "data.bin", "bytes"):
        x3p.read_x3p(path)


def test_x3p_billion_laughs(tmp_path, x3p_members):
    entities = '<!ENTITY lol "lol">' + "".join(
        f'<!ENTITY lol{i} "{("&lol%s;" % (i - 1 if i > 1 else "")) * 10}">' for i in range(1, 10))

    def laughs(xml):
        head, body = xml.split("?>", 1)
        root = re.search(r"<([\w:]+)", body).group(1)
        body = body.replace("<Comment>", "<Comment>&lol9;") if "<Comment>" in body else \
            body.replace("<Creator />", "<Creator>&lol9;</Creator>")
        return f"{head}?><!DOCTYPE {root} [{entities}]>{body}"
    path = _rezip(tmp_path / "lol.x3p", x3p_members, edit=laughs)
    assert b"<!ENTITY" in zipfile.ZipFile(path).read("main.xml")
    with _raises(path, "(?i)entit|XML"):
        x3p.read_x3p(path)


@pytest.mark.parametrize("value", ["inf", "nan", "0", "1e400"])
def test_x3p_non_finite_or_zero_spacing(tmp_path, x3p_members, value):
    def edit(xml):
        return re.sub(r"(<CX>.*?<Increment>)([^<]*)", rf"\g<1>{value}", xml, flags=re.S)
    path = _rezip(tmp_path / "inc.x3p", x3p_members, edit=edit)
    with _raises(path, "Increment|increment"):
        x3p.read_x3p(path)


def test_x3p_oversized_main_xml_is_refused(tmp_path, x3p_members, monkeypatch):
    monkeypatch.setattr(x3p, "MAX_XML_BYTES", 100)
    path = _rezip(tmp_path / "big.x3p", x3p_members)
    with _raises(path, "MAX_XML_BYTES"):
        x3p.read_x3p(path)


# --------------------------------------------------------------------------- levelling

def test_level_removes_a_known_plane_exactly_and_ignores_nan():
    ny, nx, dy, dx = 6, 9, 0.5, 0.25
    iy, ix = np.mgrid[0:ny, 0:nx]
    plane = 3.0 + 0.7 * (iy * dy) - 1.9 * (ix * dx)
    z = plane.copy()
    z[2, 3] = z[0, 8] = np.nan
    out, fit = level(z, spacing=(dy, dx), return_coefficients=True)
    assert isinstance(fit, LevelFit)
    np.testing.assert_array_equal(np.isnan(out), np.isnan(z))
    np.testing.assert_allclose(out[~np.isnan(out)], 0.0, atol=1e-12)
    np.testing.assert_allclose(fit.offset, 3.0, atol=1e-12)
    np.testing.assert_allclose(fit.slope, (0.7, -1.9), atol=1e-12)
    assert np.isnan(z[2, 3]) and z[0, 0] == 3.0                # the input is not changed

    # texture + plane: the texture is left (it is orthogonal to the plane); NaNs ignored
    rng = np.random.default_rng(1)
    texture = rng.normal(size=(ny, nx))
    a = np.column_stack([np.ones(ny * nx), iy.ravel(), ix.ravel()])
    texture -= (a @ np.linalg.lstsq(a, texture.ravel(), rcond=None)[0]).reshape(ny, nx)
    noisy = texture + plane
    np.testing.assert_allclose(level(noisy, spacing=(dy, dx)), texture, atol=1e-12)
    huge = noisy.copy()
    huge[4, 4] = np.nan
    masked = level(huge)
    assert np.isnan(masked[4, 4]) and np.all(np.isfinite(np.delete(masked.ravel(), 4 * nx + 4)))


def test_level_profile_and_mean():
    x = np.arange(20) * 0.1
    z = 2.0 - 0.5 * x
    z[7] = np.nan
    out, fit = level(z, spacing=0.1, return_coefficients=True)
    np.testing.assert_allclose(np.nan_to_num(out), 0.0, atol=1e-12)
    np.testing.assert_allclose([fit.offset, *fit.slope], [2.0, -0.5], atol=1e-12)
    flat, fit0 = level([1.0, np.nan, 3.0], order=0, return_coefficients=True)
    np.testing.assert_array_equal(flat, [-1.0, np.nan, 1.0])
    assert fit0 == LevelFit(2.0, ())


@pytest.mark.parametrize("z, kwargs, pattern", [
    ([np.nan, np.nan], {}, "measured"),
    ([1.0, np.inf], {}, "infinite"),
    ([1.0, 2.0], {"order": 2}, "order"),
    ([1.0, 2.0], {"order": True}, "order"),
    ([1.0, 2.0], {"spacing": 0.0}, "spacing"),
    (np.zeros((2, 2, 2)), {}, "shape"),
    ([[1.0, 2.0, 3.0], [np.nan] * 3], {}, "plane"),
])
def test_level_bad_input(z, kwargs, pattern):
    with pytest.raises(ValueError, match=pattern):
        level(z, **kwargs)
