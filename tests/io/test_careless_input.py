"""Careless and hostile input that used to be read silently wrong (issue 18, "Silent
misreading"): decimal commas, x y z lists in .csv / .txt, malformed first rows and NUL bytes,
x3p rotations, absurd increments and empty matrices, rounded x columns."""

from __future__ import annotations

import hashlib
import re
import zipfile

import numpy as np
import pytest

from roughgp.cli.main import main
from roughgp.io import readers, x3p
from roughgp.io.measurement import read_measurement
from roughgp.io.readers import MalformedFileError


def _write(path, text):
    path.write_text(text)
    return path


# --------------------------------------------------------------------------- decimal commas

def test_decimal_commas_with_semicolons_are_read_as_numbers(tmp_path):
    path = _write(tmp_path / "eu.csv", "x;z\n0,0;1,25\n0,5;1,31\n1,0;0,98\n1,5;1,12\n2,0;1,05\n")
    m = read_measurement(path)
    assert m.kind == "profile" and m.z.shape == (5,)
    np.testing.assert_allclose(m.z, [1.25, 1.31, 0.98, 1.12, 1.05])
    assert m.spacing == pytest.approx((0.5,))
    assert any("header line 1 skipped" in n for n in m.notes)


def test_a_long_european_profile_stays_a_profile(tmp_path):
    x = np.arange(64) * 0.5
    z = np.sin(x)
    lines = "".join(f"{a:.2f};{b:.4f}\n".replace(".", ",") for a, b in zip(x, z))
    m = read_measurement(_write(tmp_path / "eu64.csv", "Lateral um;Height um\n" + lines))
    assert m.z.shape == (64,)
    np.testing.assert_allclose(m.z, np.round(z, 4))


def test_semicolon_grid_with_decimal_commas(tmp_path):
    z, _ = readers.read_surface(_write(tmp_path / "g.txt", "1,5;2,5;3\n4;5,25;6\n"), spacing=1)
    np.testing.assert_allclose(z, [[1.5, 2.5, 3.0], [4.0, 5.25, 6.0]])


def test_a_number_with_two_decimal_marks_is_an_error(tmp_path):
    path = _write(tmp_path / "bad.csv", "x;z\n0,0;1,25\n0,5;1.234,5\n")
    with pytest.raises(MalformedFileError, match="line 3"):
        read_measurement(path)


# --------------------------------------------------------------------------- x y z lists

def _xyz_text(ny=20, nx=30, sep=","):
    rng = np.random.default_rng(1)
    z = rng.normal(size=(ny, nx))
    rows = [f"{ix * 0.5:g}{sep}{iy * 2.0:g}{sep}{z[iy, ix]:.6f}"
            for iy in range(ny) for ix in range(nx)]
    rng.shuffle(rows)
    return "x,y,z\n" + "\n".join(rows) + "\n", np.round(z, 6)


@pytest.mark.parametrize("name", ["grid.csv", "grid.txt"])
def test_xyz_lists_are_detected_by_content(tmp_path, name):
    text, z = _xyz_text()
    m = read_measurement(_write(tmp_path / name, text))
    assert m.z.shape == (20, 30)
    np.testing.assert_allclose(m.z, z)
    assert m.spacing == pytest.approx((2.0, 0.5))
    assert "xyz" in m.reader and any("x y z points" in n for n in m.notes)
    np.testing.assert_allclose(read_measurement(tmp_path / name, kind="surface").z, z)


def test_ambiguous_three_columns_are_refused(tmp_path):
    rng = np.random.default_rng(2)
    path = tmp_path / "three.csv"
    np.savetxt(path, rng.normal(size=(40, 3)), delimiter=",")
    with pytest.raises(MalformedFileError, match="ambiguous.*--kind surface"):
        read_measurement(path)
    assert read_measurement(path, kind="surface").z.shape == (40, 3)


def test_a_wide_grid_is_not_read_as_a_profile(tmp_path, capsys):
    path = tmp_path / "wide.csv"
    np.savetxt(path, np.random.default_rng(3).normal(size=(10, 30)), delimiter=",")
    with pytest.raises(MalformedFileError, match="30 columns; a profile is 1 column"):
        read_measurement(path, kind="profile")
    assert main(["texture", str(path), "--kind", "profile"]) == 2
    assert "30 columns" in capsys.readouterr().err


# --------------------------------------------------------------------------- header, NUL

def test_a_malformed_first_data_row_is_an_error_not_a_header(tmp_path):
    path = _write(tmp_path / "m.csv", "0,1.2.5\n1,1.5\n2,1.7\n")
    with pytest.raises(MalformedFileError, match="line 1: not a row of numbers"):
        readers.read_profile(path)


def test_a_line_with_a_nul_byte_is_an_error(tmp_path):
    path = tmp_path / "nul.csv"
    path.write_bytes(b"x,z\n" + b"".join(b"%d,%d.5\n" % (i, i) for i in range(3000))
                     + b"3000,1\x00.5\n3001,2\n")
    with pytest.raises(MalformedFileError, match="line 3002: a NUL byte"):
        read_measurement(path)


def test_a_non_numeric_line_after_the_header_is_an_error(tmp_path):
    path = _write(tmp_path / "h.csv", "x,z\n0,1\nvalue,2\n2,3\n")
    with pytest.raises(MalformedFileError, match="line 3"):
        readers.read_profile(path)


def test_a_skipped_header_is_reported_by_the_command(tmp_path, capsys):
    x = np.arange(64) * 0.5
    body = "".join(f"{a:g},{b:.5f}\n" for a, b in zip(x, np.sin(x)))
    path = _write(tmp_path / "p.csv", "Profile 1\nx,z\n" + body)
    assert main(["texture", str(path), "--unfiltered"]) == 0
    out = capsys.readouterr().out
    assert "header line 1 skipped: 'Profile 1'" in out and "header line 2 skipped" in out


# --------------------------------------------------------------------------- rounded x

def test_rounded_x_is_accepted_and_an_irregular_x_names_spacing(tmp_path):
    n = 300
    rows = "".join("%.6g,%.6g\n" % (i / 3, np.sin(i / 7)) for i in range(n))
    m = read_measurement(_write(tmp_path / "third.csv", rows))
    assert m.spacing[0] == pytest.approx(1 / 3, rel=1e-6) and "rounded" in m.spacing_source
    x = np.arange(50) * 1.0
    x[20] += 0.3
    path = tmp_path / "irregular.csv"
    np.savetxt(path, np.column_stack((x, np.cos(x))), delimiter=",", fmt="%.4f")
    with pytest.raises(MalformedFileError, match="not a regular grid.*--spacing"):
        read_measurement(path)


# --------------------------------------------------------------------------- x3p

@pytest.fixture
def members(tmp_path):
    path = tmp_path / "valid.x3p"
    iy, ix = np.mgrid[0:3, 0:4]
    x3p.write_x3p(path, 10.0 * iy + ix, (1.0, 1.0))
    with zipfile.ZipFile(path) as archive:
        return {name: archive.read(name) for name in archive.namelist()}


def _rezip(path, members, edit, *, top=""):
    """The file with main.xml edited (its MD5 fixed); ``top``: a top folder (the lenient path)."""
    members = dict(members)
    members["main.xml"] = edit(members["main.xml"].decode()).encode()
    members["md5checksum.hex"] = f"{hashlib.md5(members['main.xml']).hexdigest()} *main.xml\n" \
        .encode()
    with zipfile.ZipFile(path, "w") as archive:
        for name, content in members.items():
            archive.writestr(top + name, content)
    return path


def _rotation(xml):
    c, s = np.cos(0.3), np.sin(0.3)
    values = {"r11": float(c), "r12": float(-s), "r13": 0, "r21": float(s), "r22": float(c),
              "r23": 0, "r31": 0,
              "r32": 0, "r33": 1}
    element = "<Rotation>" + "".join(f"<{k}>{v!r}</{k}>" for k, v in values.items()) \
        + "</Rotation>"
    return xml.replace("</Axes>", element + "</Axes>")


def _increment(axis, value):
    return lambda xml: re.sub(rf"(<{axis}>.*?<Increment>)([^<]*)", rf"\g<1>{value}", xml,
                              flags=re.S)


CASES = {
    "rotation": (_rotation, "Record1 rotates the data"),
    "z 1e300": (_increment("CZ", "1e300"), "z increment 1e\\+300 is not a usable"),
    "x 1e-320": (_increment("CX", "1e-320"), "x increment 1e-320 m is not a usable step"),
    "y 1e300": (_increment("CY", "1e300"), "y increment 1e\\+300 m"),
    "SizeX 0": (lambda xml: re.sub(r"<SizeX>\d+</SizeX>", "<SizeX>0</SizeX>", xml),
                "empty matrix.*SizeX = 0"),
}


@pytest.mark.parametrize("top", ["", "folder/"], ids=["x3pio", "lenient"])
@pytest.mark.parametrize("case", sorted(CASES))
def test_x3p_rotations_absurd_increments_and_empty_matrices_are_refused(tmp_path, members,
                                                                          case, top):
    edit, pattern = CASES[case]
    path = _rezip(tmp_path / "bad.x3p", members, edit, top=top)
    with pytest.raises(MalformedFileError, match=pattern) as info:
        x3p.read_x3p(path)
    assert str(path) in str(info.value)


def test_x3p_identity_rotation_is_read(tmp_path, members):
    def identity(xml):
        element = "<Rotation>" + "".join(f"<r{i}{j}>{float(i == j)}</r{i}{j}>"
                                         for i in (1, 2, 3) for j in (1, 2, 3)) + "</Rotation>"
        return xml.replace("</Axes>", element + "</Axes>")
    for top in ("", "folder/"):
        h = x3p.read_x3p(_rezip(tmp_path / f"id{len(top)}.x3p", members, identity, top=top))
        assert h.z.shape == (3, 4)


# --------------------------------------------------------------------------- hostile .npy

def _npy_header(shape, descr="<f8"):
    header = f"{{'descr': '{descr}', 'fortran_order': False, 'shape': {shape}, }}"
    header += " " * (117 - len(header)) + "\n"   # 10 + 118 bytes: a 64-byte multiple
    return b"\x93NUMPY\x01\x00" + len(header).to_bytes(2, "little") + header.encode()


def test_npy_declaring_a_huge_array_is_refused_with_its_size(tmp_path):
    path = tmp_path / "huge.npy"
    path.write_bytes(_npy_header((10 ** 6, 10 ** 6)) + b"\x00" * 16)
    assert path.stat().st_size == 144
    with pytest.raises(MalformedFileError,
                       match=r"\(1000000, 1000000\).*7.28 TiB.*MAX_POINTS"):
        read_measurement(path)


def test_npy_truncated_header_and_data_are_refused(tmp_path):
    path = tmp_path / "cut.npy"
    path.write_bytes(_npy_header((4, 5))[:40])
    with pytest.raises(MalformedFileError, match="not a readable .npy header"):
        read_measurement(path)
    short = tmp_path / "short.npy"
    short.write_bytes(_npy_header((4, 5)) + b"\x00" * 24)
    with pytest.raises(MalformedFileError, match="truncated.*160 bytes"):
        read_measurement(short)


def test_npy_pickle_is_refused(tmp_path, capsys):
    path = tmp_path / "pickle.npy"
    np.save(path, np.array([{"a": 1}, None], dtype=object), allow_pickle=True)
    with pytest.raises(MalformedFileError, match="pickle"):
        read_measurement(path)
    assert main(["texture", str(path)]) == 2
    err = capsys.readouterr().err
    assert "pickle" in err and "Traceback" not in err


@pytest.mark.parametrize("header, columns", [("x in µm,z in µm\n", 2), ("", 2), ("", 1),
                                             ("index,x in µm,y in µm\n", 3)])
def test_a_table_of_one_or_two_columns_is_a_profile_even_when_a_surface_is_asked(
        tmp_path, header, columns):
    """``fit ground`` and ``fill`` ask for a surface: a profile table read as a surface 200 x 2
    points would be refused as too narrow for the fit's blocks, a reason that misleads (csv-2.csv
    of SurfaceTopography's examples: an index column and x, z)."""
    x = np.arange(200) * 0.5
    z = np.sin(x / 3.0)
    table = np.column_stack([np.arange(200), x, z][3 - columns:])
    path = tmp_path / "profile.csv"
    path.write_text(header + "\n".join(",".join(f"{v:g}" for v in row) for row in table) + "\n")
    m = read_measurement(path, kind="surface")
    assert m.kind == "profile" and m.z.shape == (200,)
    assert any("read as a profile, not as a surface" in n for n in m.notes)
    np.testing.assert_allclose(m.z, np.round(z, 5), atol=1e-5)


def test_a_surface_command_says_a_profile_table_holds_a_profile(tmp_path, capsys):
    path = tmp_path / "profile.csv"
    path.write_text("x in µm,z in µm\n" + "".join(f"{0.5 * i:g},{np.sin(i / 6):.5f}\n"
                                                  for i in range(200)))
    for command in (["fit", "ground", str(path), "--out", str(tmp_path / "m.json")],
                    ["fill", str(path), "--out", str(tmp_path / "f.csv")]):
        assert main(command) == 2
        err = capsys.readouterr().err
        assert "holds a profile" in err and "200 x 2" not in err, err
