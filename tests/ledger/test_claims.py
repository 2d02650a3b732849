"""Tests of the claims ledger (roughgp.ledger: types, checks, table, runner).

The quick checks run here; the slow ones (figures 2, 3, 5, 7, the 2-D long correlation, which
reuses figure 2's draw, and the measured data: seconds to a minute each) run in the chapter
"Claims ledger", which the tests execute, and through `roughgp reproduce`; their computations have
small-size tests in tests/experiments."""

import json
from pathlib import Path

import pytest

from roughgp import ledger
from roughgp.ledger import CLAIMS, VERDICTS, Check, Claim, runner

BOOK = Path(__file__).resolve().parents[2] / "book"
QUICK = ["eq5-duality", "fig1-acvf", "sec2.3-ma-finite", "sec2.3-arma-linear",
         "sec2.3-gp-is-arma", "sec2.3-ar-not-gp", "eq16-17-moving-average",
         "sec2.2-sampling",
         "conclusion-non-gaussian", "future-prescribed-parameters",
         "future-gap-filling", "scale-device"]


def test_the_ledger_covers_what_the_issue_asks():
    keys = ledger.claim_keys()
    assert len(keys) == len(set(keys))                      # unique keys
    for key in ("eq5-duality", "fig1-acvf", "fig2-simulation", "fig2-acvf",
                "sec3.1-error-values", "fig3-crosshatch", "fig5-periodicity",
                "fig5-dales-hills", "fig7-flaw", "conclusion-long-correlation",
                "measured-land-lay", "measured-land-check", "measured-fill"):
        assert key in keys
    assert {c.verdict for c in CLAIMS} >= {"reproduced", "reproduced with a different setup",
                                          "not reproducible as stated", "not checkable"}
    for c in CLAIMS:
        assert c.verdict in VERDICTS and c.where and c.statement and c.chapter
        page = c.chapter if "." in c.chapter else f"{c.chapter}.ipynb"
        assert (BOOK / page).is_file(), f"{c.key}: no book page {page}"
        if c.verdict != "reproduced":
            assert c.why, f"{c.key}: a verdict other than 'reproduced' must say why"
    measured = [c for c in CLAIMS if c.key.startswith("measured-") and c.check is not None]
    assert {c.chapter for c in measured} == {"measured_surfaces"}
    assert {c.verdict for c in measured} == {"beyond the paper"}


@pytest.mark.parametrize("key", QUICK)
def test_quick_checks_hold(key):
    (outcome,) = ledger.run(only=[key])
    assert outcome.error is None, outcome.error
    assert outcome.holds, f"{key} regressed: {outcome.value}"
    assert not outcome.regressed and outcome.status == "ok"


def test_unknown_key_is_refused_with_the_list():
    with pytest.raises(ValueError, match="unknown claim 'fig99'.*eq5-duality"):
        ledger.run(only=["fig99"])


def test_claims_are_validated():
    with pytest.raises(ValueError, match="verdict must be one of"):
        Claim("k", "w", "s", "", "", "proven", "", "c", lambda full: Check("1", True))
    with pytest.raises(ValueError, match="not checkable"):
        Claim("k", "w", "s", "", "", "not checkable", "why", "c", lambda full: Check("1", True))
    with pytest.raises(ValueError, match="not checkable"):
        Claim("k", "w", "s", "", "", "reproduced", "", "c", None)


def _fake(monkeypatch, check):
    fake = Claim("fake", "Sec 0", "a | claim", "1", "0", "reproduced", "", "notation", check)
    monkeypatch.setattr(runner, "CLAIMS", (fake,))
    return fake


def test_a_failing_check_regresses(monkeypatch):
    _fake(monkeypatch, lambda full: Check("2", False))
    (outcome,) = ledger.run()
    assert outcome.regressed and outcome.status == "REGRESSED"


def test_a_raising_check_is_reported_not_raised(monkeypatch):
    def broken(full):
        raise RuntimeError("boom")
    _fake(monkeypatch, broken)
    (outcome,) = ledger.run()
    assert outcome.status == "ERROR" and "RuntimeError: boom" in outcome.error


def test_full_flag_reaches_the_check(monkeypatch):
    seen = []
    _fake(monkeypatch, lambda full: seen.append(full) or Check("1", True))
    monkeypatch.delenv("ROUGHGP_FULL", raising=False)
    ledger.run(full=True)
    ledger.run()
    monkeypatch.setenv("ROUGHGP_FULL", "1")  # the one rule: no flag given, the environment
    ledger.run()
    ledger.run(full=False)
    assert seen == [True, False, True, False]


def test_figures_are_saved_and_tables_written(monkeypatch, tmp_path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    plt.close("all")              # what an earlier test in this worker left open is not ours

    def with_figure(full):
        fig, ax = plt.subplots()
        ax.plot([0, 1])
        return Check("1.0", True, fig)
    _fake(monkeypatch, with_figure)
    lines = []
    outcomes = ledger.run(figures_dir=tmp_path / "figures", progress=lines.append)
    assert (tmp_path / "figures" / "fake.png").stat().st_size > 1000
    assert outcomes[0].figure == str(tmp_path / "figures" / "fake.png")
    assert any("fake: ok" in line for line in lines)
    md, js = ledger.write(outcomes, tmp_path / "out")
    text = md.read_text()
    assert "a \\| claim" in text                              # pipes escaped in the table
    assert "**reproduced**" in text
    records = json.loads(js.read_text())
    assert records[0]["key"] == "fake" and records[0]["status"] == "ok"
    assert "(notation.ipynb)" in ledger.to_markdown(outcomes, chapter_links=True)
    short = ledger.to_markdown(outcomes, summary=True)
    assert short.splitlines()[0] == "| where | claim | verdict | status |"
    details = ledger.to_markdown_details(outcomes, chapter_links=True)
    assert "[Sec 0](notation.ipynb)" in details and "ours: 1.0" in details
    assert plt.get_fignums() == []                            # figures closed


def test_not_checkable_claims_do_not_run():
    key = next(c.key for c in CLAIMS if c.verdict == "not checkable")
    (outcome,) = ledger.run(only=[key])
    assert outcome.value == "-" and not outcome.regressed and outcome.status == "not run"
