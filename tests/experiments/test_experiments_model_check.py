"""The model check's calibration (roughgp.experiments.model_check): the synthetic measurements
and the shares outside, on a few small cases."""

from __future__ import annotations

import json

import numpy as np
import pytest

from roughgp.checking.model_check import check_model
from roughgp.checking.ranks import outside_probability
from roughgp.experiments.check_calibration import (Calibration, CalibrationCase, CheckRanks,
                                                   load_calibration)
from roughgp.experiments.model_check import calibrate, rank_check, synthetic_measurement
from roughgp.surface_models.model import FittedModel


def test_synthetic_measurements_cycle_the_chain_and_the_holes():
    kinds = []
    for index in range(4):
        truth, l_filter, z = synthetic_measurement(index, (64, 64), seed=0)
        holes = np.isnan(z).mean()
        assert (holes > 0.05) == bool(index % 2) and holes < 0.2
        assert truth.cutoffs["l_um"] == l_filter
        kinds.append((l_filter is not None, holes > 0))
    assert len(set(kinds)) == 4  # every combination of L-filter and holes
    again = synthetic_measurement(3, (64, 64), seed=0)[2]
    np.testing.assert_array_equal(np.isnan(again), np.isnan(z))
    np.testing.assert_array_equal(again[~np.isnan(again)], z[~np.isnan(z)])


def test_calibrate_counts_the_parameters_outside_per_case():
    result = calibrate(2, shape=(40, 40), n_simulations=5, n_draws=9, block=8, n_blocks=6)
    assert len(result.cases) == 2 and result.expected == 2 / 6
    fractions = result.fractions("true")
    assert set(fractions) == set(result.names)
    for case in result.cases:
        assert set(case.outside_true) <= set(result.names)
    counted = sum(len(c.outside_fitted) for c in result.cases) / (2 * len(result.names))
    assert np.isclose(result.mean_fraction("fitted"), counted)
    table = result.table()
    assert list(table.index) == list(result.names)
    assert {("true model", "0/1 (%)"), ("fitted model", "RB (%)"), ("fitted model", "PIT p")} \
        <= set(table.columns)
    assert set(table[("fitted model", "10 ± 3 %?")]) == {"too few cases"}
    fitted = result.table("fitted")
    assert list(fitted.columns) == [c for g, c in table.columns if g == "fitted model"]
    assert fitted.equals(table["fitted model"])
    assert "against the true model, 2 cases" in result.styled_table("true").to_html()
    with pytest.raises(ValueError, match="which must be 'true' or 'fitted'"):
        result.table("both")
    rb = result.outside_probabilities("fitted")
    assert rb.shape == (2, len(result.names)) and ((rb >= 0) & (rb <= 1)).all()


def test_the_plain_verdict_is_the_check_of_the_first_draws():
    """rank_check's first n_simulations draws are check_model's with the same seed."""
    truth, _, z = synthetic_measurement(3, (40, 40), seed=0)
    ranks = rank_check(truth, z, n_simulations=4, n_draws=11, seed=5)
    check = check_model(truth, z, n_simulations=4, seed=5)
    assert ranks.outside == tuple(check.outside)
    assert ranks.measured == tuple(p.measured for p in check.parameters)
    assert all(f == 11 for f in ranks.finite)
    with pytest.raises(ValueError, match="n_draws"):
        rank_check(truth, z, n_simulations=19, n_draws=10)


def test_a_model_of_the_wrong_variance_is_outside_on_sq():
    """The estimator says no when it should: checked against its true model with four times
    the variance, the measurement's Sq lies below (nearly) all simulations."""
    right, wrong = [], []
    for index in range(3):
        truth, _, z = synthetic_measurement(index, (40, 40), seed=0)
        hyper = dict(truth.hyperparameters, variance_um2=4 * truth.hyperparameters["variance_um2"])
        liar = FittedModel("eq18", hyper, truth.spacing, cutoffs=truth.cutoffs)
        for model, into in ((truth, right), (liar, wrong)):
            r = rank_check(model, z, n_simulations=19, n_draws=29, seed=index, names=("Sq",))
            into.append(outside_probability(r.above, r.below, r.finite, 19)[0])
    assert min(wrong) > 0.9 and np.mean(right) < 0.5


def test_calibration_seeds_reproduce_and_records_round_trip(tmp_path):
    kwargs = dict(shape=(40, 40), n_simulations=4, n_draws=7, block=8, n_blocks=6,
                  names=("Sq", "Ssk", "Sal"))
    first = calibrate(2, first=1, **kwargs)
    again = calibrate(2, first=1, **kwargs)
    assert [c.index for c in first.cases] == [1, 2]
    records = first.to_records()
    for a, b in zip(records, again.to_records()):
        assert {k: v for k, v in a.items() if k != "fit_seconds"} == \
            {k: v for k, v in b.items() if k != "fit_seconds"}
    path = tmp_path / "cal.jsonl"
    path.write_text("".join(json.dumps(r) + "\n" for r in records[::-1]))
    loaded = load_calibration(path)
    assert [c.index for c in loaded.cases] == [1, 2]
    np.testing.assert_allclose(loaded.outside_probabilities("fitted"),
                               first.outside_probabilities("fitted"))
    assert loaded.fractions("true") == first.fractions("true")
    with pytest.raises(ValueError, match="settings differ"):
        Calibration.from_records([records[0], dict(records[1], n_draws=8)])
    with pytest.raises(ValueError, match="twice"):
        Calibration.from_records([records[0], records[0]])


def _calibration_of_ranks(below, draws=39):
    """A Calibration of one parameter whose ranks (simulations below) are ``below``."""
    cases = []
    for index, b in enumerate(below):
        ranks = CheckRanks((0.0,), (draws - b,), (b,), (0,), (draws,), ())
        cases.append(CalibrationCase(index, None, None, False, None, ranks, ranks, 0.0))
    return Calibration(tuple(cases), ("Sq",), 19, draws, (8, 8), 0.0)


def test_matching_simulations_and_the_verdict_see_a_calibrated_and_a_pinned_parameter():
    uniform = _calibration_of_ranks(list(range(40)) * 2)   # every rank equally often
    assert uniform.matching_simulations("true") == {"Sq": 19}
    assert uniform.rb_fractions("true")["Sq"] == pytest.approx(0.1)
    assert uniform.middle_share("true")["Sq"] == pytest.approx(0.5)
    # ranks piled in the middle (a fit that pins the parameter): rarely outside, fewer
    # simulations needed for 10 %, the PIT test rejects, the verdict says no
    pinned = _calibration_of_ranks(list(range(12, 28)) * 4)
    assert pinned.rb_fractions("true")["Sq"] < 0.01
    assert pinned.matching_simulations("true")["Sq"] < 8
    assert pinned.middle_share("true")["Sq"] == 1.0
    assert pinned.pit_pvalues("true")["Sq"] < 1e-4
    assert pinned.by_verdict("true")["no"] == ["Sq"]
    # ranks at the ends (simulations too narrow): outside too often, more simulations needed
    ends = _calibration_of_ranks([0, 1, 38, 39] * 15)
    assert ends.rb_fractions("true")["Sq"] > 0.4
    assert ends.matching_simulations("true")["Sq"] > 30


def test_shares_by_model_group_the_cases_by_their_known_model():
    cal = _calibration_of_ranks([0, 20, 39, 20, 20, 0, 20, 39, 20, 20])
    by_model = cal.shares_by_model("true")
    assert sorted(by_model) == [0, 1, 2, 3, 4]
    rb = cal.outside_probabilities("true")[:, 0]
    for k in range(5):
        assert by_model[k]["Sq"] == pytest.approx(rb[[k, k + 5]].mean())
    assert by_model[0]["Sq"] == pytest.approx(1.0) and by_model[1]["Sq"] < 0.01


def _bootstrap_record(index, observed, copies, plain, outside, chance):
    return {"index": index, "shape": [64, 64], "seed": 0, "names": ["Sq", "Sal"],
            "n_simulations": 19, "n_bootstrap": len(copies[0]), "level": 0.1,
            "observed": observed, "bootstrap": copies, "p": [0.5, 0.5], "chance": chance,
            "plain_outside": plain, "outside": outside, "fit_seconds": 1.0,
            "bootstrap_seconds": 20.0}


def test_the_bootstrap_calibration_counts_shares_and_the_copies_yardstick():
    from roughgp.experiments.bootstrap_calibration import BootstrapCalibration
    records = [_bootstrap_record(1, [0.0, 3.0], [[0.0, 5.0], [2.0, 0.0]], ["Sq"], [], [0.5, 0.0]),
               _bootstrap_record(0, [4.0, np.nan], [[1.0, 2.0], [3.0, 4.0]], [], ["Sq"],
                                 [0.0, np.nan])]
    boot = BootstrapCalibration.from_records(records)
    assert [r["index"] for r in boot.records] == [0, 1]
    np.testing.assert_array_equal(boot.values("plain"), [[0, np.nan], [1, 0]])
    np.testing.assert_array_equal(boot.values("calibrated"), [[1, np.nan], [0, 0]])
    rows = {r["parameter"]: r for r in boot.summary()}
    assert rows["Sq"]["chance"] == pytest.approx(0.25) and rows["Sal"]["chance"] == 0.0
    assert np.isnan(rows["Sal"]["chance_low"])  # one finite case: no interval
    assert rows["Sq"]["within"] == "too few cases"
    # the measurements' share outside the range against the copies': Sq 1 of 2 and 1 of 4
    assert boot.outside_ranges()["Sq"] == (0.5, 0.25)
    assert boot.outside_ranges()["Sal"] == (0.0, 0.25)
    assert boot.seconds() == (1.0, 20.0)
    table = boot.table()
    assert list(table.columns) == ["plain check, % (95 %)", "calibrated check, % (95 %)",
                                   "calibrated, expected, % (95 %)", "10 ± 3 %?"]
    assert table.loc["Sq", "calibrated, expected, % (95 %)"].startswith("25.0 (")
    with pytest.raises(ValueError, match="settings differ"):
        BootstrapCalibration.from_records([records[0], {**records[1], "n_bootstrap": 9}])
    with pytest.raises(ValueError, match="occurs twice"):
        BootstrapCalibration.from_records([records[0], records[0]])
    with pytest.raises(ValueError, match="kind must be"):
        boot.values("rb")
