"""The spurious-points chapter's helpers: the per-tile noise check (calibrated on maps whose
noise is known), the Sk / Spk / Svk table of the three L-filters, the recorded run's reader."""

import json
import math

import numpy as np
import pytest

from roughgp.experiments import spurious_points as sp


def _smooth(shape=(96, 96)):
    y, x = np.mgrid[0:shape[0], 0:shape[1]]
    return np.sin(x / 15.0) + 0.5 * np.cos(y / 20.0)


def test_tile_noise_is_even_where_one_noise_variance_holds():
    rng = np.random.default_rng(0)
    z = _smooth() + 0.5 * rng.normal(size=(96, 96))
    noise = sp.tile_noise(z, np.zeros(z.shape, bool))
    assert noise.noise_sd == pytest.approx(np.full(36, 0.5), rel=0.3)
    assert np.median(noise.noise_sd) == pytest.approx(0.5, rel=0.05)
    assert noise.spread < 1.5 and not noise.noisy.any()
    assert noise.flagged_share(False) == 0.0 and math.isnan(noise.flagged_share(True))


def test_tile_noise_finds_a_band_of_larger_noise_and_its_flags():
    """A third of the map four times noisier, the flags in it: the check says no."""
    rng = np.random.default_rng(1)
    sd = np.where(np.arange(96)[None, :] < 32, 2.0, 0.5) * np.ones((96, 1))
    z = _smooth() + sd * rng.normal(size=(96, 96))
    flagged = np.zeros(z.shape, bool)
    flagged[::7, 3:30:5] = True
    z[10:20, 40:50] = np.nan  # unmeasured points are left out of the tiles
    noise = sp.tile_noise(z, flagged)
    assert noise.spread == pytest.approx(4.0, rel=0.25)
    assert noise.noisy.sum() == 12  # the two columns of tiles of the band
    assert noise.flagged_share(False) == 0.0
    assert noise.flagged_share(True) == pytest.approx(flagged.sum() / (12 * 256))
    with pytest.raises(ValueError, match="tile"):
        sp.tile_noise(np.full((40, 40), np.nan), np.zeros((40, 40), bool))


def test_stratified_texture_reports_each_l_filter():
    table = sp.stratified_texture(sp.figure3_surface((96, 96)))
    assert set(table) == {"gaussian", "stratified", "robust"}
    for kind, p in table.items():
        assert all(np.isfinite(p[k]) and p[k] > 0 for k in sp.STRATIFIED_KEYS), kind
        assert p["operators"].startswith("F: plane")
    assert "ISO 13565-1" in table["stratified"]["operators"]
    assert table["gaussian"]["Svk"] != table["robust"]["Svk"]


def test_recorded_studies_reads_its_records(tmp_path):
    assert sp.recorded_studies(tmp_path / "none.jsonl") is None
    path = tmp_path / "run.jsonl"
    path.write_text(json.dumps({"file": "a.sur", "flagged": 3}) + "\n\n"
                    + json.dumps({"file": "b.sur", "flagged": 0}) + "\n")
    assert sp.recorded_studies(path) == {"a.sur": {"file": "a.sur", "flagged": 3},
                                         "b.sur": {"file": "b.sur", "flagged": 0}}
