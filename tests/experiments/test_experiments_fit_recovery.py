"""roughgp.experiments.fit_recovery (issue 40, item 2): one recovery case per likelihood, and
the summary of fitted/true ratios the chapter reads."""

from __future__ import annotations

import math

import pytest

from roughgp.experiments.fit_recovery import (
    TRUTH,
    plot_recovery,
    recovery_case,
    recovery_summary,
    recovery_table,
)


def _record(size, likelihood, factor, seed=0):
    fitted = {**TRUTH, "variance_um2": TRUTH["variance_um2"] * factor, "angle_deg": 32.0}
    return {"size": size, "seed": seed, "likelihood": likelihood, "fitted": fitted,
            "seconds": 1.0}


def test_the_summary_is_the_median_ratio_and_the_spread_of_its_log():
    records = [_record(128, "whittle", f, seed) for seed, f in enumerate((0.8, 1.0, 1.25))]
    s = recovery_summary(records, 128, "whittle")
    assert s["cases"] == 3 and s["variance_um2"][0] == pytest.approx(1.0)
    assert s["variance_um2"][1] == pytest.approx(math.log(1.25), rel=1e-9)  # logs -l, 0, l
    assert s["lambda_a_um"] == (pytest.approx(1.0), pytest.approx(0.0))
    assert s["angle"] == pytest.approx(2.0)
    assert recovery_summary(records, 256, "whittle") is None
    assert "| 128² | whittle | 3 | 1.000, 0.2" in recovery_table(records)
    plot_recovery(records).clf()


@pytest.mark.parametrize("likelihood", ["blocks", "whittle"])
def test_one_case_fits_a_map_of_the_truth(likelihood):
    record = recovery_case(64, 0, likelihood)
    assert record["likelihood"] == likelihood and record["size"] == 64
    assert 0.3 < record["fitted"]["variance_um2"] / TRUTH["variance_um2"] < 3.0
    with pytest.raises(ValueError, match="likelihood must be one of blocks, whittle"):
        recovery_case(64, 0, "exact")
