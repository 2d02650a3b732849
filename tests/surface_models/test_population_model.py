"""The eq18-population rung (roughgp.surface_models.population_model, issue 40 item 3): the
population's centre and spread from several measurements or the tiles of one map, regions that
share one value pooled to a narrow spread and regions that differ to a wide one, draws of one
region each, the model file's schema, and the command with several files."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from roughgp.experiments.held_out import eq18_model
from roughgp.surface_models.model import FittedModel, ModelFileError
from roughgp.surface_models.population_draw import SPREAD_NAMES, region_parameters
from roughgp.surface_models.population_model import fit_population_model
from model_file_refusal import assert_refused

SHAPE = (48, 48)


def _regions(spread, count, seed):
    """``count`` maps of regions whose variance is 1 um^2 times exp(spread g), g standard
    normal per region (lengths 6 and 3 um, lay 30 deg, noise 0.01 um^2)."""
    rng = np.random.default_rng(seed)
    return [eq18_model(math.exp(spread * rng.standard_normal()), 6.0, 3.0, 30.0, 0.01)
            .simulate(SHAPE, seed=rng) for _ in range(count)]


@pytest.fixture(scope="module")
def alike():
    return fit_population_model(_regions(0.0, 6, 0), 1.0, l=None, n_draws=10, seed=0)


@pytest.fixture(scope="module")
def differing():
    return fit_population_model(_regions(0.8, 6, 1), 1.0, l=None, n_draws=10, seed=0)


def test_regions_alike_give_the_common_value_and_a_narrow_spread(alike):
    hp = alike.model.hyperparameters
    assert hp["regions"] == 6
    assert 0.75 < hp["variance_um2"] < 1.33
    assert 4.0 < hp["lambda_a_um"] < 9.0 and 2.0 < hp["lambda_b_um"] < 4.5
    assert abs(hp["angle_deg"] - 30.0) < 10.0
    assert hp["log_variance_sd"] < 0.35


def test_regions_that_differ_give_a_wide_spread(alike, differing):
    assert differing.pooled_of("log variance").tau > 0.3
    assert differing.model.hyperparameters["log_variance_sd"] > \
        2 * alike.model.hyperparameters["log_variance_sd"]
    assert differing.pooled_of("log variance").p_homogeneity < 0.01


def test_one_map_s_tiles_are_its_regions():
    fit = fit_population_model(_regions(0.0, 1, 2)[0], 1.0, l=None, tiles=(2, 2), n_draws=10)
    assert fit.model.hyperparameters["regions"] == 4
    assert fit.model.fit["tiles"] == [2, 2]
    with pytest.raises(ValueError, match="at least 2 regions"):
        fit_population_model(_regions(0.0, 1, 2)[0], 1.0, l=None, tiles=(1, 1), n_draws=10)


def test_each_draw_is_its_own_region_and_the_seed_repeats_them(differing):
    model = differing.model
    draws = model.simulate((32, 32), seed=4, n_samples=40)
    np.testing.assert_array_equal(draws, model.simulate((32, 32), seed=4, n_samples=40))
    fixed = FittedModel.from_dict({**model.to_dict(), "hyperparameters": {
        **model.hyperparameters, **{name: 0.0 for name in SPREAD_NAMES}}})
    same = fixed.simulate((32, 32), seed=4, n_samples=40)
    spread = np.std(np.log(draws.var(axis=(1, 2))))
    assert spread > 2 * np.std(np.log(same.var(axis=(1, 2))))
    regions = region_parameters(model.hyperparameters, model.spacing,
                                np.random.default_rng(0), 200)
    log_var = np.log([r["variance_um2"] for r in regions])
    assert np.median(log_var) == pytest.approx(math.log(model.hyperparameters["variance_um2"]),
                                               abs=0.15)
    assert np.std(log_var) > 0.8 * model.hyperparameters["log_variance_sd"]


def test_few_regions_never_draw_a_length_far_beyond_the_grid(differing):
    """Four regions: t with 2 degrees of freedom, and a wide spread of the log lengths. A draw
    of 80 times the pooled length needed a torus of minutes (or none); the lengths drawn stay
    within FAR_BEYOND times the grid's longer side, and every draw comes back."""
    from roughgp.inference.whittle_fit import FAR_BEYOND
    hp = {**differing.model.hyperparameters, "regions": 4, "log_lambda_a_sd": 1.0,
          "log_lambda_b_sd": 1.0}
    free = region_parameters(hp, (1.0, 1.0), np.random.default_rng(2), 400)
    held = region_parameters(hp, (1.0, 1.0), np.random.default_rng(2), 400, longest=64.0)
    assert max(r["lambda_a_um"] for r in free) > 64.0  # what the cap is for
    assert max(r["lambda_a_um"] for r in held) == 64.0
    assert [r["variance_um2"] for r in held] == [r["variance_um2"] for r in free]
    model = FittedModel.from_dict({**differing.model.to_dict(), "hyperparameters": hp})
    draws = model.simulate((16, 16), seed=2, n_samples=60)
    assert draws.shape == (60, 16, 16) and np.isfinite(draws).all()
    assert FAR_BEYOND * 16 == 64.0


def test_the_model_file_round_trips_and_refuses_spoiled_fields(differing, tmp_path):
    path = differing.model.save(tmp_path / "population.json")
    again = FittedModel.load(path)
    assert again.hyperparameters == differing.model.hyperparameters
    assert "population of 6 regions" in again.describe()
    record = json.loads(path.read_text())

    def set_field(name, value):
        return lambda r: r["hyperparameters"].__setitem__(name, value)

    assert_refused(record, set_field("log_variance_sd", -0.1), "log_variance_sd")
    assert_refused(record, set_field("log_lambda_a_sd", 7.0), "log_lambda_a_sd")
    assert_refused(record, set_field("angle_sd_deg", math.nan), "angle_sd_deg")
    assert_refused(record, set_field("regions", 1), "regions must be an integer in [2,")
    assert_refused(record, set_field("regions", 2.5), "regions must be an integer")
    assert_refused(record, lambda r: r["hyperparameters"].pop("log_lambda_b_sd"),
                   "lacks log_lambda_b_sd")
    assert_refused(record, lambda r: r.__setitem__("marginal", {"skewness": 0.5,
                                                                "kurtosis": 4.0}),
                   "marginal must be null")
    with pytest.raises(ValueError, match="no single kernel"):
        again.kernel()


def test_a_spread_that_implies_heights_beyond_a_metre_is_refused(differing):
    record = differing.model.to_dict()
    record["hyperparameters"].update(variance_um2=1e9, log_variance_sd=3.0)
    with pytest.raises(ModelFileError, match="log_variance_sd"):
        FittedModel.from_dict(record).simulate((8, 8), seed=0)


def _run(capsys, *argv):
    from roughgp.cli.main import main
    code = main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return code, out, err


def test_fit_ground_of_several_files_and_its_refusals(tmp_path, capsys):
    paths = []
    for k, z in enumerate(_regions(0.8, 3, 3)):
        paths.append(tmp_path / f"region{k}.npy")
        np.save(paths[-1], z)
    out = tmp_path / "part.json"
    code, text, err = _run(capsys, "fit", "ground", *paths, "--model", "population",
                           "--l-filter", "none", "--out", out)
    assert code == 0, err
    assert "eq 18 over a population of 3 regions" in text and "a new region" in text
    record = json.loads(out.read_text())
    assert [f["file"] for f in record["data"]["files"]] == [p.name for p in paths]
    code, text, err = _run(capsys, "check", out, paths[0], "--simulations", 4)
    assert code == 0, err
    np.save(tmp_path / "coarse.npy", np.load(paths[0])[::2, ::2])
    for argv, words in (
            (("--model", "eq18"), "several files (2) are for --model population"),
            (("--model", "population", "--part", "left"), "leave out --part"),
            (("--model", "population", "--anchors", 2, 2), "leave out --anchors"),
            (("--model", "population", "--out", paths[1]), "--out"),
    ):
        code, _, err = _run(capsys, "fit", "ground", paths[0], paths[1], *argv)
        assert code == 2 and words in err, err
    code, _, err = _run(capsys, "fit", "ground", paths[0], tmp_path / "coarse.npy", "--model",
                        "population", "--spacing", 1, "--l-filter", "none")
    assert code == 0, err     # one --spacing for every file: they share it, whatever the shape
    from roughgp.io.writers import write_heights
    write_heights(tmp_path / "coarse.x3p", np.load(paths[1]), 2.0, "a coarser grid")
    write_heights(tmp_path / "fine.x3p", np.load(paths[0]), 1.0, "a finer grid")
    code, _, err = _run(capsys, "fit", "ground", tmp_path / "fine.x3p",
                        tmp_path / "coarse.x3p", "--model", "population")
    assert code == 2 and "must share one spacing" in err, err


def test_regions_too_unlike_for_one_population_are_refused():
    maps = _regions(0.0, 3, 5)
    maps[1] = maps[1] * 1e4     # a factor of 1e8 in variance: another part altogether
    with pytest.raises(ValueError, match="not regions of one part"):
        fit_population_model(maps, 1.0, l=None, n_draws=10)


def test_maps_of_several_sizes_share_the_first_map_s_cut_offs():
    """The L-filter's "auto" cut-off follows the map's size: the first map resolves it and
    every other map is filtered alike (the model keeps one chain for all its regions)."""
    from roughgp.metrology.filters import default_cutoffs
    rng = np.random.default_rng(3)
    model = eq18_model(1.0, 6.0, 3.0, 30.0, 0.01)
    maps = [model.simulate((64, 64), seed=rng), model.simulate((48, 48), seed=rng),
            model.simulate((32, 40), seed=rng)]
    fit = fit_population_model(maps, 1.0, l="auto", n_draws=10, seed=0)
    first, last = default_cutoffs(maps[0], (1.0, 1.0)).l, default_cutoffs(maps[-1], (1.0, 1.0)).l
    assert first != last
    assert fit.model.cutoffs["l_um"] == first
