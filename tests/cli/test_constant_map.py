"""Issue 44 part 2, a constant map: fit (every model, every marginal), texture (filtered or not)
and --spurious refuse a map whose heights do not vary (after the F-operator: a plane is flat
too) by name, exit 2, rather than write a model of variance 4e-34 or print Sku 16 for a flat
map (roughgp.common.checks.check_varies). Refusal, not NaN: a flat map has no parameter to
report."""

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


@pytest.mark.parametrize("options", [(), ("--unfiltered",), ("--spurious",)])
def test_texture_refuses_a_flat_map(capsys, tmp_path, flat, options):
    if "--unfiltered" in options and "plane" in flat.name:
        pytest.skip("a tilted plane, unfiltered, has heights that vary")
    code, out, err = _run(capsys, "texture", flat, *options)
    assert code == 2 and CONSTANT in err and str(flat) in err, err
    assert "Sku" not in out


def test_the_library_refuses_a_constant_map():
    z = np.full((32, 32), -1.5)
    with pytest.raises(ValueError, match=CONSTANT):
        roughgp.fit(z, 1.0)
    with pytest.raises(ValueError, match=CONSTANT):
        roughgp.texture(z, 1.0)


def test_a_map_that_varies_a_little_is_measured(capsys, tmp_path):
    z = 1e3 + 1e-3 * np.random.default_rng(0).normal(size=(32, 32))
    path = tmp_path / "rough.npy"
    np.save(path, z)
    code, out, err = _run(capsys, "texture", path)
    assert code == 0 and "Sq" in out, err
