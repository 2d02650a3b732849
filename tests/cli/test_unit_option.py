"""``--unit`` does what its help says: the heights' unit of a .npy or text file, the heights'
and spacing's unit of an instrument file (replacing the one it states), refused for .x3p."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
from cli_run import run as _run

DATA = Path(__file__).resolve().parents[2] / "data"


def _texture(capsys, tmp_path, path, *unit):
    out = tmp_path / f"t{len(unit)}.json"
    code, _, err = _run(capsys, "texture", path, *unit, "--unfiltered", "--json", out,
                        "--force")
    assert code == 0, err
    return json.loads(out.read_text())


def test_the_help_says_what_unit_does(capsys):
    try:
        _, out, _ = _run(capsys, "texture", "--help")
    except SystemExit:
        out = capsys.readouterr().out
    text = " ".join(out.split())
    for words in ("for a .npy or text file the heights' unit", "x columns and --spacing stay "
                  "in um", "for an instrument file the unit of its heights and spacing",
                  "refused for .x3p"):
        assert words in text, words


def test_a_npy_files_heights_are_in_the_unit_given(capsys, tmp_path):
    path = tmp_path / "s.npy"
    np.save(path, np.random.default_rng(0).standard_normal((32, 32)))
    um, mm = _texture(capsys, tmp_path, path), _texture(capsys, tmp_path, path, "--unit", "mm")
    assert mm["height_unit_from"].startswith("mm (as given)")
    assert mm["spacing_um"] == um["spacing_um"]
    np.testing.assert_allclose(mm["parameters"]["Sq"], 1000 * um["parameters"]["Sq"], rtol=1e-9)


def test_an_instrument_files_heights_and_spacing_take_the_unit_given(capsys, tmp_path):
    path = DATA / "sur-2.sur"
    stated, given = _texture(capsys, tmp_path, path), _texture(capsys, tmp_path, path,
                                                                "--unit", "nm")
    assert "from the file" in stated["height_unit_from"]
    assert given["height_unit_from"].startswith("nm (as given)")
    factor = given["parameters"]["Sq"] / stated["parameters"]["Sq"]
    np.testing.assert_allclose(np.array(given["spacing_um"]) / stated["spacing_um"], factor,
                               rtol=1e-9)
    assert factor != 1.0


def test_an_x3p_refuses_a_unit(capsys):
    code, _, err = _run(capsys, "texture", DATA / "sample-land.x3p", "--unit", "mm")
    assert code == 2 and "an .x3p file stores metres" in err
