"""The verbs (roughgp.api): importable from ``import roughgp`` without numpy or torch, and each
the function of the library it names, called with the measurement's heights and spacing."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import roughgp
from roughgp.checking.model_check import check_model
from roughgp.filling.measured import fill_measured_surface
from roughgp.io.measurement import Measurement, read_measurement
from roughgp.metrology.texture_report import filtered_parameters
from roughgp.models import surfaces
from roughgp.surface_models.fit import fit_profile_model, fit_surface_model
from roughgp.surface_models.model import FittedModel

ROOT = Path(__file__).resolve().parents[2]
VERBS = ("read", "fit", "simulate", "check", "fill", "texture")

EQ18 = {"variance_um2": 1.0, "lambda_a_um": 8.0, "lambda_b_um": 3.0, "angle_deg": 30.0,
        "noise_variance_um2": 0.05}


def test_import_roughgp_imports_neither_torch_nor_numpy():
    probe = ("import sys, roughgp\n"
             f"assert all(callable(getattr(roughgp, v)) for v in {VERBS!r})\n"
             "print(' '.join(sorted(sys.modules)))")
    done = subprocess.run([sys.executable, "-c", probe], cwd=ROOT, capture_output=True,
                          text=True, env={"PYTHONPATH": str(ROOT), "PATH": ""}, timeout=120)
    assert done.returncode == 0, done.stderr
    modules = set(done.stdout.split())
    assert "torch" not in modules and "numpy" not in modules


def test_the_verbs_are_the_api_modules_and_documented():
    from roughgp import api
    for verb in VERBS:
        assert getattr(roughgp, verb) is getattr(api, verb)
        assert verb in roughgp.__all__ and verb in api.__all__
        assert len(getattr(api, verb).__doc__) > 200


def _measurement(seed=3, shape=(48, 48)):
    z = surfaces.ground(shape, variance=1.0, lengthscales=(8.0, 3.0), angle=np.pi / 6,
                        noise_variance=0.05, seed=seed)
    z[10:14, 20:26] = np.nan
    return Measurement(z, (1.0, 1.0), "given")


def test_read_is_read_measurement():
    path = ROOT / "data" / "sample-land.x3p"
    a, b = roughgp.read(path), read_measurement(path)
    assert np.array_equal(a.z, b.z, equal_nan=True) and a.spacing == b.spacing


def test_texture_of_a_measurement_or_its_heights():
    m = _measurement()
    report = roughgp.texture(m, l=None)
    same = filtered_parameters(m.z, m.spacing, l=None)
    assert report.parameters == pytest.approx(same.parameters, nan_ok=True)
    assert roughgp.texture(m.z, 1.0, l=None).parameters == \
        pytest.approx(same.parameters, nan_ok=True)


def test_fit_of_a_surface_is_fit_surface_model():
    m = _measurement()
    model = roughgp.fit(m, block=12, n_blocks=4)
    same = fit_surface_model(m.z, m.spacing, block=12, n_blocks=4).model
    assert isinstance(model, FittedModel)
    assert model.hyperparameters == pytest.approx(same.hyperparameters)
    with pytest.raises(ValueError, match="rung"):
        roughgp.fit(m, model="spline")


def test_fit_of_a_profile_is_eq21():
    x = np.arange(256) * 0.5
    z = np.sin(2 * np.pi * x / 12.0) + 0.1 * np.random.default_rng(1).standard_normal(x.size)
    model = roughgp.fit(z, 0.5, num_mixtures=2, n_candidates=2)
    same = fit_profile_model(z, 0.5, num_mixtures=2, n_candidates=2).model
    assert model.equation == "eq21" and model.kind == "profile"
    for key, value in same.hyperparameters.items():
        assert np.allclose(model.hyperparameters[key], value)
    with pytest.raises(ValueError, match="eq21"):
        roughgp.fit(z, 0.5, model="eq18")


def test_simulate_a_model_its_file_or_a_preset(tmp_path, monkeypatch):
    model = FittedModel("eq18", EQ18, (1.0, 1.0), cutoffs={"form": "plane", "s_um": None,
                                                            "l_um": 10.0})
    z = roughgp.simulate(model, (32, 40), seed=1)
    assert np.array_equal(z, model.simulate((32, 40), seed=1))
    path = model.save(tmp_path / "model.json")
    assert np.array_equal(roughgp.simulate(str(path), (32, 40), seed=1), z)
    assert roughgp.simulate(model, (32, 40), seed=1, n_samples=2).shape == (2, 32, 40)
    chained = roughgp.simulate(model, (32, 40), seed=1, chain=True)
    assert np.nanstd(chained) < np.std(z)  # the L-filter of 10 um takes variance away
    ground = roughgp.simulate("ground", (16, 16), seed=2)
    assert np.array_equal(ground, surfaces.ground((16, 16), variance=10.0,
                                                  lengthscales=(500.0, 5.0),
                                                  angle=np.pi / 6, seed=2))
    monkeypatch.setattr(surfaces, "honed", lambda shape, steps, **kw: (shape, steps, kw))
    assert roughgp.simulate("honed", (16, 16), seed=2) == ((16, 16), surfaces.FIGURE_3,
                                                           {"spacing": 1.0, "seed": 2})


def test_check_is_check_model():
    m = _measurement()
    model = FittedModel("eq18", EQ18, (1.0, 1.0))
    result = roughgp.check(model, m, n_simulations=4, seed=0)
    same = check_model(model, m.z, m.spacing, n_simulations=4, seed=0)
    assert result.outside == same.outside
    assert [p.rank for p in result.parameters] == [p.rank for p in same.parameters]


def test_fill_is_fill_measured_surface():
    m = _measurement()
    model = FittedModel("eq18", EQ18, (1.0, 1.0))
    filled = roughgp.fill(m, model=model)
    same = fill_measured_surface(m.z, spacing=m.spacing, model=model)
    assert np.allclose(filled.filled, same.filled)
    assert not np.isnan(filled.filled).any()
    with pytest.raises(ValueError, match="FittedModel of a surface"):
        roughgp.fill(m, model=FittedModel("eq21", {"weights_um2": [1.0],
                                                   "frequencies_per_um": [0.1],
                                                   "spectral_variances_per_um2": [0.01],
                                                   "noise_variance_um2": 0.1}, (1.0,)))
