"""The IAAFT heights out of sample (roughgp.experiments.iaaft_held_out): the synthetic maps and
the summary's shares."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.stats

from roughgp.experiments import iaaft_held_out as ih


def test_the_lognormal_maps_are_skewed_and_seeded():
    z = ih.synthetic_map("lognormal", 0)
    assert z.shape == ih.SHAPE and scipy.stats.skew(z.ravel()) > 1.0
    np.testing.assert_array_equal(z, ih.synthetic_map("lognormal", 0))
    assert abs(scipy.stats.skew(ih.synthetic_map("gaussian", 0).ravel())) < 0.5
    with pytest.raises(ValueError, match="kind must be one of gaussian, lognormal"):
        ih.synthetic_map("weibull", 0)


def test_the_summary_averages_each_case_s_share_of_the_13():
    def case(index, gaussian, iaaft):
        return {"kind": "gaussian", "index": index, "seed": 0, "seconds": 1.0,
                "checks": {"gaussian": {"fitted": [], "held_out": gaussian},
                           "iaaft": {"fitted": [], "held_out": iaaft},
                           "iaaft-predictive": {"fitted": [], "held_out": []}}}
    records = [case(0, ["Sq"], ["Sq", "Sa", "Sk"]), case(1, [], ["Sku"])]
    table = ih.summary(records).set_index(["heights", "half"])
    assert table.loc[("iaaft", "held-out"), "outside (mean of 13)"] == pytest.approx(2 / 13)
    assert table.loc[("gaussian", "held-out"), "Sq outside"] == 0.5
    assert table.loc[("gaussian", "fitted"), "outside (mean of 13)"] == 0
    assert set(table["cases"]) == {2}
    # at most 2 of 13 outside: case 1 only for IAAFT (3 then 1 outside), both for Gaussian
    assert table.loc[("iaaft", "held-out"), "≤ 2 outside"] == 0.5
    assert table.loc[("gaussian", "held-out"), "≤ 2 outside"] == 1.0
    # its 95 % upper bound: the mean + 1.96 sd / sqrt(2) of (0, 1), clipped to 1
    assert table.loc[("iaaft", "held-out"), "≤ 2 outside, 95 % high"] == pytest.approx(
        min(1.0, 0.5 + 1.96 * np.std([0, 1], ddof=1) / np.sqrt(2)))
    assert table.loc[("gaussian", "held-out"), "≤ 2 outside, 95 % high"] == 1.0


def test_a_marginal_added_later_merges_into_its_case(tmp_path):
    """A marginal run later for the recorded cases is a line of its own; load_records merges
    the lines of one case, and the summary leaves out a marginal where a case lacks it."""
    import json
    first = {"kind": "gaussian", "index": 0, "seed": 0, "seconds": 2.0,
             "checks": {"gaussian": {"fitted": [], "held_out": ["Sq"]}}}
    later = {"kind": "gaussian", "index": 0, "seed": 0, "seconds": 1.0,
             "checks": {"iaaft-tiles": {"fitted": [], "held_out": []}}}
    lines = [first, later, {**first, "index": 1}, {**later, "index": 1}, {**first, "index": 2}]
    path = tmp_path / "r.jsonl"
    path.write_text("\n".join(json.dumps(r) for r in lines) + "\n")
    records = ih.load_records(path)
    assert len(records) == 3 and records[0]["seconds"] == 3.0
    assert set(records[0]["checks"]) == {"gaussian", "iaaft-tiles"}
    table = ih.summary(records).set_index(["heights", "half"])
    assert table.loc[("iaaft-tiles", "held-out"), "cases"] == 2
    assert table.loc[("gaussian", "held-out"), "cases"] == 3
    assert "iaaft" not in set(table.index.get_level_values(0))


def test_per_parameter_gives_each_parameter_s_share_interval_and_verdict():
    """200 cases with Sq outside in 20 (10 %, undecided: its interval reaches past 13 %) and Sv
    in 60 (30 %: no); a parameter never outside: 0 % [0 %, 0 %], no. The half as given."""
    records = [{"kind": "gaussian", "index": i, "seed": 0, "seconds": 1.0,
                "checks": {"iaaft-tiles": {"fitted": ["Sq"] * (i < 100),
                                           "held_out": ["Sq"] * (i % 10 == 0)
                                           + ["Sv"] * (i % 10 < 3)}}}
               for i in range(200)]
    table = ih.per_parameter(records).set_index(["kind", "heights"])
    row = table.loc[("gaussian", "iaaft-tiles")]
    assert row["cases"] == 200 and len(table) == 1
    assert row["Sq"] == "10% [6%, 14%] ?"
    assert row["Sv"].startswith("30% [") and row["Sv"].endswith(" no")
    assert row["Sa"] == "0% [0%, 0%] no"
    assert ih.per_parameter(records, half="fitted").loc[0, "Sq"].startswith("50% [")
    with pytest.raises(ValueError, match="half must be 'fitted' or 'held_out'"):
        ih.per_parameter(records, half="B")
