"""``roughgp simulate --from MODEL --predictive-from SOURCE`` and ``roughgp.simulate(...,
predictive=...)`` (issue 40: the fit's uncertainty carried into the simulations): the same
seed gives the same surface, the predictive draws spread more than the plug-in ones where the
fitted part varies, and every misuse is refused before anything is drawn or written."""

from __future__ import annotations

import numpy as np
import pytest

from roughgp.experiments.held_out import synthetic_map
from cli_run import run


@pytest.fixture(scope="module")
def fitted(tmp_path_factory):
    """A 64 x 128 map whose left half has one tile four times rougher, and two models of that
    half: the measured PSD with the measured heights, and eq 18."""
    from roughgp.cli.main import main
    folder = tmp_path_factory.mktemp("predictive")
    z, _, _ = synthetic_map("stationary", 7, shape=(64, 128))
    z = z.copy()
    z[:16, :16] *= 4.0
    np.save(folder / "map.npy", z)
    for name, options in (("psd", ("--model", "psd", "--marginal", "iaaft")),
                          ("eq18", ("--block", 12, "--blocks", 4))):
        code = main([str(a) for a in ("fit", "ground", folder / "map.npy", "--part", "left",
                                      *options, "--l-filter", "none",
                                      "--out", folder / f"{name}.json")])
        assert code == 0
    return folder


def _simulate(capsys, folder, out, *options):
    return run(capsys, "simulate", "--from", folder / "psd.json", "--shape", 64, 64,
               "--out", folder / out, *options)


def test_tiles_same_seed_same_surface_and_not_the_plug_in_one(capsys, fitted):
    options = ("--predictive-from", "tiles", "--fitted", fitted / "map.npy", "--seed", 3)
    code, _, err = _simulate(capsys, fitted, "a.npy", *options)
    assert code == 0, err
    assert "drawn first (--predictive-from tiles)" in err and "drawn model: measured PSD" in err
    assert _simulate(capsys, fitted, "b.npy", *options)[0] == 0
    assert _simulate(capsys, fitted, "plug.npy", "--seed", 3)[0] == 0
    a, b, plug = (np.load(fitted / f) for f in ("a.npy", "b.npy", "plug.npy"))
    assert np.array_equal(a, b)
    assert not np.allclose(a, plug)


def test_predictive_draws_spread_as_the_fitted_tiles_do(fitted):
    """One tile of 16 four times rougher: the tiles drawn with replacement hold it 0, 1, 2 ...
    times, so the predictive draws' Sq varies far more than the plug-in draws' does."""
    import roughgp
    from roughgp.cli.simulate_model import fitted_map
    model = roughgp.surface_models.model.FittedModel.load(fitted / "psd.json")
    z, spacing = fitted_map(model, fitted / "map.npy")
    plug = roughgp.simulate(model, (64, 64), seed=1, n_samples=12)
    drawn = roughgp.simulate(model, (64, 64), seed=1, n_samples=12, predictive="tiles",
                             fitted=(z, spacing))
    spread = [np.std(np.log(np.std(d.reshape(12, -1), axis=1))) for d in (plug, drawn)]
    assert spread[1] > 2 * spread[0], spread


def test_refits_draw_an_eq18_model_of_its_own(capsys, fitted):
    code, _, err = run(capsys, "simulate", "--from", fitted / "eq18.json", "--seed", 5,
                       "--predictive-from", "refits", "--out", fitted / "r.npy")
    assert code == 0, err
    assert "one bootstrap refit" in err and err.count("eq 18") >= 2
    assert np.load(fitted / "r.npy").shape == (64, 64)


@pytest.mark.parametrize("options, message", [
    (("--fitted", "map.npy"), "--fitted is the map the tile bootstrap draws from"),
    (("--predictive-from", "tiles"), "give it as --fitted FILE"),
    (("--predictive-from", "refits", "--fitted", "map.npy"), "--fitted is for --predictive-from "
                                                               "tiles"),
    (("--predictive-from", "tiles", "--fitted", "other.npy"), "is not the file the model was "
                                                               "fitted on"),
    (("--predictive-from", "sandwich"), "--predictive-from sandwich: "),
    (("--predictive-from", "tiles", "--fitted", "map.npy", "--out", "map.npy"), "map.npy"),
])
def test_misuse_is_refused_before_anything_is_written(capsys, fitted, options, message):
    np.save(fitted / "other.npy", np.load(fitted / "map.npy") + 1.0)
    before = (fitted / "map.npy").read_bytes()
    options = tuple(fitted / o if str(o).endswith(".npy") else o for o in options)
    out = () if "--out" in options else ("--out", fitted / "refused.npy")
    code, _, err = run(capsys, "simulate", "--from", fitted / "psd.json", "--seed", 1, *out,
                       *options)
    assert code == 2 and message in err, err
    assert "Traceback" not in err
    assert not (fitted / "refused.npy").exists()
    assert (fitted / "map.npy").read_bytes() == before


def test_a_kind_refuses_the_model_options(capsys, tmp_path):
    code, _, err = run(capsys, "simulate", "--predictive-from", "tiles", "ground", "--shape",
                       8, 8, "--out", tmp_path / "g.npy")
    assert code == 2 and "--predictive-from is for a draw from a model file" in err


def test_a_map_with_other_points_than_the_fit_used_is_refused(capsys, fitted):
    """A model file without the SHA-256 (edited, or written by the library), and a map that
    holds a point the fit did not use (as after fit --spurious): the tiles would hold it."""
    import json
    record = json.loads((fitted / "psd.json").read_text())
    del record["data"]["sha256"]
    (fitted / "nosha.json").write_text(json.dumps(record))
    z = np.load(fitted / "map.npy")
    z[5, 5] = np.nan
    np.save(fitted / "holed.npy", z)
    code, _, err = run(capsys, "simulate", "--from", fitted / "nosha.json", "--seed", 1,
                       "--predictive-from", "tiles", "--fitted", fitted / "holed.npy",
                       "--out", fitted / "holed-out.npy")
    assert code == 2 and "the fit left points out" in err, err
    assert not (fitted / "holed-out.npy").exists()


def test_the_library_refuses_a_fitted_map_without_predictive_and_presets(fitted):
    import roughgp
    with pytest.raises(ValueError, match="give it with predictive='tiles'"):
        roughgp.simulate(fitted / "psd.json", (8, 8), seed=0, fitted=(np.zeros((8, 8)), 1.0))
    with pytest.raises(ValueError, match="predictive are for a fitted model"):
        roughgp.simulate("ground", (8, 8), seed=0, predictive="refits")
    with pytest.raises(ValueError, match="n_samples must be"):
        roughgp.simulate(fitted / "psd.json", (8, 8), seed=0, predictive="tiles",
                         n_samples=0, fitted=(np.zeros((64, 64)), 1.0))


def test_the_fitted_file_is_checked_before_anything_is_drawn(capsys, fitted):
    np.save(fitted / "other2.npy", np.load(fitted / "map.npy") * 2.0)
    code, _, err = run(capsys, "simulate", "--from", fitted / "psd.json", "--seed", 1,
                       "--predictive-from", "tiles", "--fitted", fitted / "other2.npy",
                       "--out", fitted / "early.npy")
    assert code == 2 and "is not the file the model was fitted on" in err
    assert "drawing" not in err and not (fitted / "early.npy").exists()


def test_the_parser_s_sources_are_the_library_s():
    from roughgp.checking.predictive import SOURCES
    from roughgp.cli.options import PREDICTIVE_SOURCES
    assert PREDICTIVE_SOURCES == SOURCES


def test_a_csv_of_unequal_spacing_is_refused_before_the_draw(capsys, fitted):
    import json
    record = json.loads((fitted / "eq18.json").read_text())
    record["spacing_um"] = [1.0, 2.0]
    (fitted / "aniso.json").write_text(json.dumps(record))
    code, _, err = run(capsys, "simulate", "--from", fitted / "aniso.json", "--seed", 1,
                       "--out", fitted / "aniso.csv")
    assert code == 2 and "a .csv stores one spacing" in err, err
    assert "drawn in" not in err and not (fitted / "aniso.csv").exists()


def test_a_fit_with_spurious_points_left_out_draws_its_tiles_with_spurious(capsys, tmp_path):
    """``fit ground --spurious`` left the map's spikes out; ``simulate --predictive-from tiles
    --fitted MAP`` refuses the map (its tiles would hold them) and says to give --spurious,
    which finds them as the fit did (on the whole file, the fit's seed) and draws; the same
    seed, the same surface."""
    from roughgp.experiments.spurious_points import draw_surface
    z = draw_surface("eq 18", (64, 64), 5)
    z[10, 20] += 40.0
    z[40, 50] -= 40.0
    np.save(tmp_path / "spiked.npy", z)
    code, _, err = run(capsys, "fit", "ground", tmp_path / "spiked.npy", "--spurious",
                       "--model", "psd", "--marginal", "iaaft", "--l-filter", "none",
                       "--seed", 4, "--out", tmp_path / "m.json")
    assert code == 0, err
    draw = ("simulate", "--from", tmp_path / "m.json", "--predictive-from", "tiles",
            "--fitted", tmp_path / "spiked.npy", "--seed", 2)
    code, _, err = run(capsys, *draw, "--out", tmp_path / "a.npy")
    assert code == 2 and "give --spurious too" in err, err
    assert not (tmp_path / "a.npy").exists()
    for name in ("a.npy", "b.npy"):
        code, _, err = run(capsys, *draw, "--spurious", "--out", tmp_path / name)
        assert code == 0, err
        assert "--spurious:" in err
    a, b = np.load(tmp_path / "a.npy"), np.load(tmp_path / "b.npy")
    assert a.shape == (64, 64) and np.array_equal(a, b)


@pytest.mark.parametrize("options, words", [
    (("--spurious",), "give it with --predictive-from tiles --fitted FILE"),
    (("--predictive-from", "refits", "--spurious"), "give it with --predictive-from tiles"),
])
def test_spurious_without_the_fitted_map_is_refused(capsys, fitted, options, words):
    code, _, err = _simulate(capsys, fitted, "sp.npy", "--seed", 1, *options)
    assert code == 2 and words in err, err
    assert not (fitted / "sp.npy").exists()


def test_a_kind_refuses_spurious(capsys, tmp_path):
    code, _, err = run(capsys, "simulate", "--spurious", "ground", "--shape", 8, 8,
                       "--out", tmp_path / "g.npy")
    assert code == 2 and "--spurious is for a draw from a model file" in err


def test_a_model_file_without_order_scores_is_noted(capsys, fitted):
    """A model file of IAAFT heights written before the order-score keys draws as it did, and
    the command says why its draws fall short and what to do; a file with the keys, no note."""
    import json
    record = json.loads((fitted / "psd.json").read_text())
    assert "order_scores" in record["marginal"]
    del record["marginal"]["order_scores"]
    (fitted / "old.json").write_text(json.dumps(record))
    for name, noted in (("old.json", True), ("psd.json", False)):
        code, _, err = run(capsys, "simulate", "--from", fitted / name, "--seed", 1,
                           "--out", fitted / f"drawn-{name}.npy")
        assert code == 0, err
        assert ("keyed at the Hazen positions" in err and "fit it again" in err) == noted
