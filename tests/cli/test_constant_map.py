"""Issue 44 part 2, a constant map (after the F-operator: a plane is flat too): fit (every model,
every marginal) and --spurious refuse it by name, exit 2, rather than write a model of variance
4e-34 or flag 2 of its points (roughgp.common.checks.check_varies); texture reports the
parameters of a flat surface, 0 or undefined (nan), as it did --unfiltered, rather than Sku 16
of the operators' rounding."""

from __future__ import annotations

import numpy as np
import pytest

import roughgp
from cli_run import run as _run

CONSTANT = "are constant"


@pytest.fixture(params=["constant", "plane"])
def flat(tmp_path, request):
    y, x = np.mgrid[0:32, 0:32].astype(float)
    z = np.full((32, 32), 3.0) if request.param == "constant" else 2.0 + 0.01 * x - 0.03 * y
    path = tmp_path / f"{request.param}.npy"
    np.save(path, z)
    return path


@pytest.mark.parametrize("options", [("--model", "eq18"), ("--model", "psd"),
                                     ("--model", "matern"), ("--model", "sm"),
                                     ("--marginal", "iaaft")])
def test_fit_ground_refuses_a_flat_map(capsys, tmp_path, flat, options):
    out = tmp_path / "m.json"
    code, _, err = _run(capsys, "fit", "ground", flat, *options, "--out", out)
    assert code == 2 and CONSTANT in err and str(flat) in err, err
    assert not out.exists()


@pytest.mark.parametrize("options", [(), ("--l-filter", "none")])
def test_texture_of_a_flat_map_reports_a_flat_surface(capsys, flat, options):
    """It printed Sku 16, Ssk 3e-14 and Sal 0.5 um, of the operators' rounding: now the
    parameters of a flat surface, 0 or undefined (nan), as --unfiltered reports them."""
    code, out, err = _run(capsys, "texture", flat, *options)
    assert code == 0, err
    assert "heights after the operators are constant" in " ".join(out.split())
    values = {line.split()[0]: line.split()[1] for line in out.splitlines()
              if line.startswith("  S") and len(line.split()) >= 2}
    assert float(values["Sq"]) == 0.0
    assert all(values[name] == "nan" for name in ("Ssk", "Sku", "Sal", "Str"))


def test_texture_spurious_refuses_a_flat_map(capsys, flat):
    """--spurious flagged 2 points of a flat map."""
    code, out, err = _run(capsys, "texture", flat, "--spurious")
    assert code == 2 and CONSTANT in err and str(flat) in err, err
    assert "Sku" not in out


def test_the_library_refuses_to_fit_a_constant_map():
    z = np.full((32, 32), -1.5)
    with pytest.raises(ValueError, match=CONSTANT):
        roughgp.fit(z, 1.0)
    assert np.isnan(roughgp.texture(z, 1.0).parameters["Sku"])


def test_a_map_that_varies_a_little_is_measured(capsys, tmp_path):
    z = 1e3 + 1e-3 * np.random.default_rng(0).normal(size=(32, 32))
    path = tmp_path / "rough.npy"
    np.save(path, z)
    code, out, err = _run(capsys, "texture", path)
    assert code == 0 and "Sq" in out, err
