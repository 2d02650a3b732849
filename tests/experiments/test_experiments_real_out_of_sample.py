"""The real maps out of sample (roughgp.experiments.real_out_of_sample): the windows and halves,
the rows read from batch records, and the summary's counts (the best in hindsight included)."""

from __future__ import annotations

import pytest

from roughgp.experiments import real_out_of_sample as ros


@pytest.mark.parametrize("shape, expected", [
    ((256, 918), (0, 203, 256, 512, "left")),
    ((512, 512), (128, 0, 256, 512, "left")),
    ((256, 256), (0, 0, 256, 256, "left")),
    ((300, 150), (0, 0, 300, 150, "top")),
    ((1000, 300), (244, 22, 512, 256, "top")),
])
def test_the_window_is_central_and_halved_along_its_longer_axis(shape, expected):
    assert ros.split_window(shape) == expected


def _record(path, fitted, held, error=None):
    return {"path": path, "sha256": "ab", "seed": 1, "shape": [256, 512], "error": error,
            "seconds": {"total": 10.0}, "fit": {"rung": "eq18"},
            "check": None if error else {"outside": fitted,
                                         "parameters": {"Sq": {"measured": 2.0}}},
            "held_out": None if error else {"outside": held,
                                            "parameters": {"Sq": {"measured": 3.0}}}}


def test_a_row_names_the_map_and_the_parameters_outside_on_each_half():
    row = ros.row_of("eq18", _record("w/opd-1_opd.x3p", ["Sq"], ["Sq", "Sal"]))
    assert row["map"] == "opd-1.opd" and row["model"] == "eq18"
    assert row["fitted_outside"] == ["Sq"] and row["held_out_outside"] == ["Sq", "Sal"]
    refused = ros.row_of("auto", _record("w/di-3_di.x3p", None, None, error="too small"))
    assert refused["error"] == "too small" and refused["held_out_outside"] is None


def test_the_summary_counts_refused_maps_as_not_reproduced_and_the_hindsight_bound():
    p13 = [f"P{i}" for i in range(13)]
    rows = [ros.row_of("eq18", _record("a.x3p", ["Sq"], ["Sq"])),
            ros.row_of("eq18", _record("b.x3p", p13, p13)),
            ros.row_of("psd-iaaft", _record("a.x3p", [], p13[:5])),
            ros.row_of("psd-iaaft", _record("b.x3p", [], [], error="refused"))]
    table = ros.summary(rows).set_index("model")
    assert table.loc["eq18", "B: ≤ 2 outside"] == 0.5
    assert table.loc["psd-iaaft", "A: ≤ 2 outside"] == 0.5     # b refused: not reproduced
    assert table.loc["psd-iaaft", "fitted"] == 1
    assert table.loc["psd-iaaft", "B: mean outside"] == 5
    best = table.loc["best in hindsight"]
    assert best["B: ≤ 2 outside"] == 0.5 and best["B: mean outside"] == 7  # a: 1, b: 13
    cells = ros.per_map(rows)
    assert cells.loc["a", "eq18"] == "1 / 1" and cells.loc["b", "psd-iaaft"] == "refused"
    assert list(cells.columns) == ["Sq B / A", "eq18", "psd-iaaft"]
    assert cells.loc["a", "Sq B / A"] == 1.5
    by_parameter = ros.outside_by_parameter(rows)
    assert by_parameter.loc["Sq", "eq18"] == 1 and by_parameter.loc["Sq", "psd-iaaft"] == 0
    assert len(by_parameter) == 13   # the parameters of the check, whatever the rows name


def test_the_windows_bytes_and_so_their_batch_seeds_depend_on_the_map_alone(tmp_path,
                                                                           monkeypatch):
    """Windows written with the day's date gave every fresh --work folder other bytes, other
    batch seeds, and --model auto other rungs on some maps."""
    from roughgp.common.digests import file_sha256
    from roughgp.experiments.real_maps import real_file
    digests = []
    for day, folder in (("0", "a"), ("86400", "b")):  # written on two days
        monkeypatch.setenv("SOURCE_DATE_EPOCH", day)
        groups = ros.write_windows(tmp_path / folder, (real_file("opd-1.opd"),))
        digests += [file_sha256(path) for paths in groups.values() for path in paths]
    assert len(digests) == 2 and digests[0] == digests[1]


def test_the_runs_without_their_spurious_points_get_their_own_hindsight_bound():
    """A model run with --spurious measures the halves without their spikes: its rows neither
    set the maps' Sq ratio nor join the hindsight bound of the heights as measured."""
    p13 = [f"P{i}" for i in range(13)]
    clean = _record("a.x3p", [], [])
    clean["check"]["parameters"]["Sq"]["measured"] = 1.0
    rows = [ros.row_of("psd-iaaft", _record("a.x3p", [], p13[:5])),
            ros.row_of("psd-iaaft-spurious", clean)]
    assert ros.MODELS[[m.name for m in ros.MODELS].index("psd-iaaft-spurious")].spurious
    table = ros.summary(rows).set_index("model")
    assert table.loc["best in hindsight", "B: mean outside"] == 5
    assert table.loc["best in hindsight, spurious left out", "B: mean outside"] == 0
    assert ros.sq_ratio(rows, "a") == 1.5
    assert ros.summary(rows[:1]).iloc[-1]["model"] == "best in hindsight"
