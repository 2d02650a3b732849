"""The periodic-mark rung (roughgp.surface_models.periodic_model): a turned surface's feed,
mark and roughness recovered, its draws keep the data's periodicity and short-wavelength share,
the model file round trip, the schema's refusals and the command's fall-back."""

from __future__ import annotations

import numpy as np
import pytest

from roughgp.experiments import turned_surface as ts
from roughgp.metrology import levelling
from roughgp.models import turned
from roughgp.surface_models.model import FittedModel, ModelFileError
from roughgp.surface_models.periodic_model import NoPeriodError, fit_periodic_model

SHAPE = (96, 1536)


def _run(capsys, *argv):
    from roughgp.cli.main import main
    code = main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return code, out, err


@pytest.fixture(scope="module")
def raw():
    return turned.turned_surface(SHAPE, 1.0, ts.PARAMS, seed=4)


@pytest.fixture(scope="module")
def fitted(raw):
    return fit_periodic_model(raw, 1.0)


def test_the_feed_the_mark_and_the_roughness_are_recovered(fitted):
    hp = fitted.model.hyperparameters
    truth = ts.PARAMS
    assert hp["feed_direction_deg"] == 0
    assert abs(hp["feed_um"] / truth.feed - 1) < 0.01
    assert abs(fitted.marks.height - truth.rt) < 0.5
    # the roughness on top: the side-flow field (exponential, sd 0.1 um, 3 um) and the noise
    assert 0.5 < hp["variance_um2"] / truth.flow_roughness ** 2 < 2.0
    assert 0.5 < hp["lambda_a_um"] / truth.flow_lengthscale < 2.0
    assert 0.5 < hp["noise_variance_um2"] / truth.noise_sd ** 2 < 2.0
    assert hp["shift_sd_um"] < 4 * truth.feed_jitter and hp["depth_sd_um"] < 4 * truth.depth_jitter


def test_its_draws_keep_the_periodicity_that_eq22_loses(fitted, raw):
    """Figure 7's two measures (roughgp.metrology.periodicity): the draws' periodicity at 1..5
    feeds within 0.05 of the data's, their short-wavelength share within a factor 1.5."""
    z = levelling.level(raw, spacing=1.0)
    data = ts.measure_flaw([z], ts.PARAMS.feed)
    draws = fitted.model.simulate(SHAPE, seed=1, n_samples=4)
    sims = ts.measure_flaw([levelling.level(d, spacing=1.0) for d in draws], ts.PARAMS.feed)
    assert np.all(np.abs(sims.mean_periodicity - data.mean_periodicity) < 0.05)
    assert 1 / 1.5 < sims.mean_short_share / data.mean_short_share < 1.5
    assert ts.flaw_shown(sims, data) == (False, False)


def test_the_model_file_round_trip_and_seeded_draws(fitted, tmp_path):
    path = fitted.model.save(tmp_path / "p.json")
    back = FittedModel.load(path)
    assert back.describe() == fitted.model.describe()
    a, b = back.simulate((40, 600), seed=3), back.simulate((40, 600), seed=3)
    np.testing.assert_array_equal(a, b)
    assert not np.array_equal(a, back.simulate((40, 600), seed=4))
    assert np.isfinite(a).all()


def test_marks_along_y_are_found_on_the_transposed_map(raw, fitted):
    across = fit_periodic_model(raw.T.copy(), 1.0)
    hp, hp0 = across.model.hyperparameters, fitted.model.hyperparameters
    assert hp["feed_direction_deg"] == 90
    assert hp["feed_um"] == pytest.approx(hp0["feed_um"])
    assert across.model.simulate((600, 40), seed=0).shape == (600, 40)


def test_a_stationary_map_holds_no_mark():
    z = np.random.default_rng(0).standard_normal((64, 512))
    with pytest.raises(NoPeriodError, match="along x: no feed mark.*along y"):
        fit_periodic_model(z, 1.0)


def _record(model, **changes):
    record = model.to_dict()
    record["hyperparameters"].update(changes)
    return record


@pytest.mark.parametrize("changes, words", [
    (dict(feed_direction_deg=45), "feed_direction_deg must be 0"),
    (dict(mark_um=[0.0, 1.0]), "mark_um must be a list of 4 to 8192"),
    (dict(shift_sd_um=1000.0), "shift_sd_um must be in [0, feed_um / 4"),
    (dict(origin_um=1e5), "origin_um must be in [0, feed_um"),
    (dict(depth_rho=1.5), "depth_rho must be a finite number in [0, 0.99]"),
    (dict(feed_um=1.0), "feed_um must be at least 4 spacings"),
])
def test_the_schema_refuses_a_bad_field(fitted, changes, words):
    with pytest.raises(ModelFileError) as error:
        FittedModel.from_dict(_record(fitted.model, **changes))
    assert words in str(error.value)


def test_it_has_no_single_kernel(fitted):
    with pytest.raises(ValueError, match="no single kernel"):
        fitted.model.kernel()


def test_the_command_fits_simulates_and_falls_back(capsys, tmp_path, raw):
    np.save(tmp_path / "turned.npy", raw[:64, :1100])
    code, text, err = _run(capsys, "fit", "ground", tmp_path / "turned.npy", "--model",
                           "periodic", "--l-filter", "none", "--out", tmp_path / "p.json")
    assert code == 0, err
    flat = " ".join(text.split())
    assert "periodic mark: feed" in flat and "whole marks" in flat
    code, _, err = _run(capsys, "simulate", "--from", tmp_path / "p.json", "--shape", 32, 700,
                        "--seed", 1, "--out", tmp_path / "sim.npy")
    assert code == 0, err
    assert np.load(tmp_path / "sim.npy").shape == (32, 700)
    np.save(tmp_path / "noise.npy", np.random.default_rng(1).standard_normal((48, 48)))
    code, text, err = _run(capsys, "fit", "ground", tmp_path / "noise.npy", "--model",
                           "periodic", "--l-filter", "none", "--out", tmp_path / "n.json")
    assert code == 0, err
    flat = " ".join(text.split())
    assert "no periodic feed mark" in flat and "falling back to --model auto" in flat
    assert FittedModel.load(tmp_path / "n.json").equation != "periodic-mark"


@pytest.mark.parametrize("extra, words", [
    (("--feed", 250), "--feed applies to --model periodic only"),
    (("--model", "periodic", "--feed", 2), "feed must be in [4 spacings"),
    (("--model", "periodic", "--feed", -3), "--feed must be in"),
    (("--model", "periodic", "--marginal", "johnson"), "--model periodic draws Gaussian"),
])
def test_fit_periodic_refuses_what_does_not_apply(capsys, tmp_path, raw, extra, words):
    np.save(tmp_path / "turned.npy", raw[:32, :1100])
    code, _, err = _run(capsys, "fit", "ground", tmp_path / "turned.npy", *extra,
                        "--l-filter", "none", "--out", tmp_path / "never.json")
    assert code == 2 and words in err, err
    assert not (tmp_path / "never.json").exists()


def test_holes_are_no_trouble(raw):
    """A map with a whole column and a block unmeasured: the same feed, no warning."""
    import warnings
    z = raw.copy()
    z[:, 700] = np.nan
    z[20:50, 100:400] = np.nan
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        holes = fit_periodic_model(z, 1.0)
    assert abs(holes.model.hyperparameters["feed_um"] / ts.PARAMS.feed - 1) < 0.01
    assert holes.model.data["missing_fraction"] > 0.05


@pytest.fixture(scope="module")
def profile():
    return turned.turned_profile(4096, 1.0, seed=7)[1]


def test_a_profile_gives_its_marks_and_its_roughness(profile):
    from roughgp.surface_models.periodic_model import fit_periodic_profile
    fitted = fit_periodic_profile(profile, 1.0)
    hp = fitted.model.hyperparameters
    truth = turned.RUBERT_LIKE
    assert fitted.model.kind == "profile"
    assert abs(hp["feed_um"] / truth.feed - 1) < 0.01
    assert 0.5 < hp["noise_variance_um2"] / truth.noise_sd ** 2 < 2.0
    back = FittedModel.from_dict(fitted.model.to_dict())
    draws = back.simulate(2048, seed=1, n_samples=3)
    assert draws.shape == (3, 2048) and np.isfinite(draws).all()
    np.testing.assert_array_equal(draws, back.simulate(2048, seed=1, n_samples=3))


def test_the_profile_command_fits_and_falls_back(capsys, tmp_path, profile):
    np.save(tmp_path / "p.npy", profile)
    code, text, err = _run(capsys, "fit", "profile", tmp_path / "p.npy", "--model", "periodic",
                           "--out", tmp_path / "p.json")
    assert code == 0, err
    assert FittedModel.load(tmp_path / "p.json").equation == "periodic-mark-profile"
    np.save(tmp_path / "n.npy", np.random.default_rng(2).standard_normal(512))
    code, text, err = _run(capsys, "fit", "profile", tmp_path / "n.npy", "--model", "periodic",
                           "--mixtures", 2, "--candidates", 2, "--out", tmp_path / "n.json")
    assert code == 0, err
    assert "falling back to eq 21" in " ".join(text.split())
    assert FittedModel.load(tmp_path / "n.json").equation == "eq21"
    code, _, err = _run(capsys, "fit", "profile", tmp_path / "p.npy", "--feed", 250,
                        "--out", tmp_path / "never.json")
    assert code == 2 and "--feed applies to --model periodic only" in err
    holes = profile.copy()
    holes[10] = np.nan
    np.save(tmp_path / "h.npy", holes)
    code, _, err = _run(capsys, "fit", "profile", tmp_path / "h.npy", "--model", "periodic",
                        "--out", tmp_path / "never.json")
    assert code == 2 and "the periodic-mark fit needs a complete profile" in err
    assert not (tmp_path / "never.json").exists()


def test_fill_kriges_what_the_marks_leave(fitted, raw):
    """The holes filled by the map's own marks plus eq 18's kriging: within the roughness
    (sd about 0.1 um) of the truth, where the heights span some 10 um."""
    from roughgp.filling.measured import fill_measured_surface
    z = raw.copy()
    z[30:50, 300:340] = np.nan
    z[70:74, 900:980] = np.nan
    holes = np.isnan(z)
    filled = fill_measured_surface(z, spacing=1.0, model=fitted.model, seed=0).filled
    error = filled[holes] - raw[holes]
    assert np.sqrt(np.mean(error ** 2)) < 0.2 < raw.std()
