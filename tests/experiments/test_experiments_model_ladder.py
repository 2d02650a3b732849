"""The ladder of models (roughgp.experiments.model_ladder): the run of one rung on a map whose
answer is known, the failures kept, the best rung and the share, the reasons, the crop."""

from __future__ import annotations

import dataclasses
import json
import types

import numpy as np
import pytest

from roughgp.checking.model_check import SURFACE_PARAMETERS
from roughgp.common import plotting
from roughgp.experiments import model_ladder as ml
from roughgp.surface_models.model import FittedModel

SHAPE = (64, 64)
TRUTH = FittedModel("eq18", {"variance_um2": 1.0, "lambda_a_um": 6.0, "lambda_b_um": 3.0,
                             "angle_deg": 30.0, "noise_variance_um2": 0.01}, (1.0, 1.0),
                    cutoffs={"form": "plane", "s_um": None, "l_um": None})


@pytest.fixture(scope="module")
def measurement():
    """A synthetic eq 18 "measurement": the answer (eq 18 describes it) is known."""
    return TRUTH.simulate(SHAPE, seed=3)


def _known(scale):
    """A rung that returns the true model with its variances times ``scale`` (no fit)."""
    def fit(z, spacing, *, form, seed, data):
        hp = dict(TRUTH.hyperparameters)
        hp["variance_um2"] *= scale
        hp["noise_variance_um2"] *= scale
        return types.SimpleNamespace(model=dataclasses.replace(TRUTH, hyperparameters=hp))
    return ml.Rung(f"truth-x{scale:g}", f"the truth, variance x {scale:g}", fit)


def test_the_check_says_no_to_a_wrong_model_and_yes_to_the_true_one(measurement):
    right = ml.run_rung(measurement, (1.0, 1.0), _known(1.0), seed=0)
    wrong = ml.run_rung(measurement, (1.0, 1.0), _known(4.0), seed=0)
    assert right.n_outside <= 2
    # twice the sd: every amplitude parameter far outside, the shape parameters not
    assert {"Sq", "Sa", "Sp", "Sv", "Sz", "Sk"} <= set(wrong.outside)
    assert "Sku" not in wrong.outside
    assert wrong.n_outside >= 7
    # the held-out score uses the kernel: the GP beats linear interpolation, calibrated band
    assert right.rmse_ratio < 1 and 0.85 < right.coverage <= 1
    reasons = ml.reasons(wrong)
    assert any(r.startswith("the amplitude") and "Sq" in r for r in reasons)
    assert (ml.reasons(right) == []) == (right.n_outside == 0)


def test_eq18_fitted_to_an_eq18_measurement_leaves_few_outside(measurement):
    result = ml.run_rung(measurement, (1.0, 1.0), "eq18", seed=0)
    assert result.n_outside <= 2, result.outside
    assert result.fit_seconds > 0 and result.check is not None
    assert 0.5 < result.rmse_ratio < 1.0
    again = ml.run_rung(measurement, (1.0, 1.0), "eq18", seed=0)
    assert again.outside == result.outside and again.rmse_ratio == result.rmse_ratio


def test_spikes_put_the_tails_outside_the_gaussian_rung(measurement):
    spiky = measurement.copy()
    rng = np.random.default_rng(0)
    spiky.flat[rng.choice(spiky.size, 12, replace=False)] += 8.0
    result = ml.run_rung(spiky, (1.0, 1.0), "eq18", seed=0)
    assert {"Sku", "Sp"} <= set(result.outside)
    assert any(r.startswith("the height distribution") for r in ml.reasons(result))


def test_a_failed_fit_is_kept_with_its_error():
    def fails(z, spacing, *, form, seed, data):
        raise ValueError("lambda on a bound")
    result = ml.run_rung(np.zeros((32, 32)), 1.0, ml.Rung("bad", "bad", fails))
    assert result.outside is None and result.n_outside is None
    assert "lambda on a bound" in result.description
    assert ml.reasons(result) == [result.description]


def _result(file, rung, n, ratio):
    outside = None if n is None else SURFACE_PARAMETERS[:n]
    return ml.RungResult(file, rung, (0, 0, 8, 8), outside, None, ratio, 0.95, 1.0, 1.0, "")


A, B, C = "opd-1.opd", "di-3.di", "sample-land.x3p"


def test_best_rung_and_share(tmp_path):
    rungs = tuple(ml.RUNGS)[:3]
    results = (_result(A, rungs[0], 5, 0.8), _result(A, rungs[1], 1, 0.9),
               _result(A, rungs[2], 1, 0.7),          # a tie broken by the held-out score
               _result(B, rungs[0], 3, 0.8), _result(B, rungs[1], None, np.nan),
               _result(B, rungs[2], 3, 0.8),          # a full tie: the simpler rung
               _result(C, rungs[0], 0, np.nan), _result(C, rungs[1], 0, 0.9),
               _result(C, rungs[2], 4, 0.5))
    ladder = ml.Ladder(results, (A, B, C), rungs, 8, 1.0)
    assert [ladder.best(f).rung for f in (A, B, C)] == [rungs[2], rungs[0], rungs[1]]
    assert ladder.reproduced() == [A, C]
    assert ladder.share_reproduced() == pytest.approx(2 / 3)
    assert ladder.share_reproduced(max_outside=3) == 1.0
    first = SURFACE_PARAMETERS[0]
    assert ladder.files_outside(rungs[0])[first] == 2       # 5, 3 and 0 outside: Sq in 2 ...
    assert ladder.files_outside(rungs[0])[SURFACE_PARAMETERS[4]] == 1   # ... the 5th in 1
    assert ladder.files_outside()[first] == 2               # the best: 1, 3, 0 outside
    counts = ladder.counts()
    assert counts.shape == (3, 3) and np.isnan(counts.loc[B, rungs[1]])
    table = ladder.table()
    assert table["best"].sum() == 3 and len(table) == 9
    assert table.loc[4, "which"].startswith("failed")
    fig = ml.plot_ladder(ladder)
    assert fig.get_size_inches()[0] <= 8.8
    sizes = plotting.font_sizes_on_page(fig)
    assert min(v for v in sizes.values() if v is not None) >= plotting.MIN_FONT_PT
    assert not plotting.overlapping_tick_labels(fig)
    import matplotlib.pyplot as plt
    plt.close(fig)  # a figure left open would be counted by a later test (tests/ledger)
    # the records: written, read back, the same verdicts
    path = tmp_path / "records.jsonl"
    path.write_text("".join(json.dumps(r.to_record()) + "\n" for r in results))
    again = ml.recorded_ladder(path, size=8)
    assert again.files == ladder.files and again.rungs == ladder.rungs
    assert [again.best(f).rung for f in again.files] == [ladder.best(f).rung
                                                          for f in ladder.files]
    assert ml.recorded_ladder(tmp_path / "none.jsonl") is None
    path.write_text("".join(json.dumps(r.to_record()) + "\n" for r in results[:-1]))
    assert ml.recorded_ladder(path, size=8).files == (A, B)   # C lacks a rung: left out
    lines = ml.verdict_lines(again)
    assert len(lines) == 3 and lines[0].startswith("`opd-1.opd` (white-light")
    assert "1 of 13 outside" in lines[0] and "The paper's eq 18: 5 outside" in lines[0]
    table = ml.markdown_table(again).splitlines()
    assert len(table) == 2 + 3 and "**1**" in table[2] and "| failed |" in table[3]
    narrow = ml.markdown_table(again, per_rung=False).splitlines()
    assert narrow[0].count("|") == 6 and "best model" in narrow[0]
    best_name = ml._short(again.best(again.files[0]).rung).replace("\n", " ")
    assert f"| {best_name} |" in narrow[2]


def test_crop_window_and_bad_input():
    from roughgp.experiments.real_maps import crop_window   # the crop the ladder reads
    assert crop_window((256, 918), 128) == (64, 395, 128, 128)
    assert crop_window((100, 300), 128) == (0, 86, 100, 128)
    with pytest.raises(ValueError, match="size must be >= 16"):
        crop_window((64, 64), 4)
    with pytest.raises(ValueError, match="rungs must be among"):
        ml.model_ladder(["opd-1.opd"], ["eq19"])
    with pytest.raises(ValueError, match="name must be one of the files"):
        ml.model_ladder(["nothing.x3p"], ["eq18"])
    assert ml.crop_size(full=False) == 128 and ml.crop_size(full=True) == 256
