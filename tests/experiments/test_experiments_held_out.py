"""roughgp.experiments.held_out (issue 40): the synthetic maps of known models behind the
out-of-sample calibration, one case end to end, and the table of shares."""

from __future__ import annotations

import numpy as np
import pytest

from roughgp.experiments.held_out import (
    KINDS,
    held_out_case,
    outside_shares,
    shares_table,
    synthetic_map,
)


@pytest.mark.parametrize("kind", KINDS)
def test_each_kind_is_a_map_with_the_true_models_of_its_halves(kind):
    z, left, right = synthetic_map(kind, 0, shape=(32, 64))
    again, _, _ = synthetic_map(kind, 0, shape=(32, 64))
    assert z.shape == (32, 64) and np.array_equal(z, again, equal_nan=True)
    assert np.isnan(z).any() == (kind == "holes")
    same = left.hyperparameters == right.hyperparameters
    assert same == (kind in ("stationary", "holes"))
    if kind == "gradient":
        ratio = right.hyperparameters["variance_um2"] / left.hyperparameters["variance_um2"]
        assert 1.5 < ratio < 3.0
        assert np.nanstd(z[:, 48:]) > np.nanstd(z[:, :16])


def test_an_unknown_kind_is_refused():
    with pytest.raises(ValueError, match="kind must be one of stationary, holes"):
        synthetic_map("ramp", 0)


def test_one_case_end_to_end_and_its_table():
    record = held_out_case("gradient", 0, shape=(32, 64), n_simulations=9, n_models=0)
    assert set(record["outside"]) == {"in-sample", "held-out", "held-out-true"}
    assert set(record["tiles"]["Sq"]) == {"left", "right"}
    fake = [{"kind": "stationary", "outside": {"held-out": ["Sq"] if i < 3 else []},
             "tiles": {n: {"left": 0.0, "right": 0.25} for n in ("Sq", "Sal", "Str", "Std")}}
            for i in range(10)]
    shares = outside_shares(fake, "stationary", "held-out")
    assert shares["cases"] == 10 and shares["Sq"] == pytest.approx(0.3)
    assert outside_shares(fake, "stationary", "predictive") is None
    table = shares_table(fake + [record])
    assert "| stationary | held-out | 10 | 2% | 30% |" in table
    assert "| stationary | held-out half | 25% |" in table
    assert "| gradient | in-sample | 1 |" in table


def test_the_sandwich_variant_needs_a_whittle_fit_and_is_recorded():
    with pytest.raises(ValueError, match="sandwich=True needs likelihood='whittle'"):
        held_out_case("stationary", 0, shape=(32, 64), n_models=0, sandwich=True)
    record = held_out_case("stationary", 1, shape=(32, 64), n_simulations=9, n_models=0,
                           likelihood="whittle", sandwich=True)
    assert "predictive-sandwich" in record["outside"] or record["sandwich_refused"]
    assert set(record["outside"]) >= {"in-sample", "held-out", "held-out-true"}


def test_the_calibration_table_gives_each_share_an_interval_and_a_verdict():
    from roughgp.experiments.held_out import calibration_table
    fake = [{"kind": "stationary" if i % 2 else "holes", "likelihood": "whittle",
             "outside": {"held-out": ["Sq"] if i < 60 else [],
                         "held-out-true": ["Sq"] if i % 10 == 0 else []}}
            for i in range(200)]
    fake.append({"kind": "gradient", "likelihood": "whittle", "outside": {"held-out": ["Sq"]}})
    table = calibration_table(fake, names=("Sq", "Sa"), likelihood="whittle")
    assert "| held-out | 200 | 30% [24%, 37%] no | 0% [0%, 2%] no |" in table
    assert "| held-out-true | 200 | 10% [7%, 15%] ? |" in table
    assert "in-sample" not in table
    from roughgp.experiments.held_out import (calibration_summary, plot_calibration,
                                              summary_markdown)
    summary = calibration_summary(fake, names=("Sq", "Sa"), likelihood="whittle")
    assert [(r["check"], r["cases"], r["no"], r["undecided"], r["beyond"]) for r in summary] == \
        [("held-out", 200, 2, 0, ["Sq", "Sa"]), ("held-out-true", 200, 1, 1, ["Sa"])]
    assert "| held-out | 200 | 15.0% | 0 | 0 | 2 | Sq, Sa |" in summary_markdown(summary)
    fig = plot_calibration(fake, names=("Sq", "Sa"), likelihood="whittle")
    assert len(fig.axes[0].get_legend().get_texts()) == 3  # the band and two checks


def test_two_hundred_cases_cannot_show_a_share_within_10_percent_plus_minus_3():
    from roughgp.experiments.held_out import cases_to_decide
    needed = cases_to_decide()
    assert 400 < needed < 1000
    assert cases_to_decide(0.1, 0.05) <= 200 < needed
