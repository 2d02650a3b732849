"""The ledger's test switches (roughgp.ledger.runner): ``ROUGHGP_LEDGER_FAULT`` reports claims as
regressed (a fault injection, marked so), ``ROUGHGP_LEDGER_ONLY`` narrows a run; and how a
regression is rendered for the book (in red) and by ``roughgp reproduce`` (exit 1).

The chapter's side (the page written and red, its test item failing) is
tests/booktools/test_regressed_claim.py."""

import os
import subprocess
import sys
from pathlib import Path

import pytest

from roughgp import ledger
from roughgp.cli.main import main
from roughgp.ledger import Check, Claim, runner
from roughgp.ledger.runner import FAULT_ENV, FAULT_MARK, ONLY_ENV, regression_notice


@pytest.fixture(autouse=True)
def _no_switches(monkeypatch):
    for name in (FAULT_ENV, ONLY_ENV):
        monkeypatch.delenv(name, raising=False)


def _fakes(monkeypatch):
    ran = []

    def check(key, holds=True):
        return lambda full: ran.append(key) or Check(f"value of {key}", holds)
    claims = (Claim("a", "Sec 1", "claim a", "1", "0", "reproduced", "", "notation", check("a")),
              Claim("b", "Sec 2", "claim b", "2", "0", "reproduced", "", "notation", check("b")),
              Claim("c", "Sec 3", "claim c", "", "", "not checkable", "why", "notation", None))
    monkeypatch.setattr(runner, "CLAIMS", claims)
    return ran


def test_the_fault_makes_a_claim_regress_marked_as_injected(monkeypatch):
    ran = _fakes(monkeypatch)
    monkeypatch.setenv(FAULT_ENV, " b ")
    a, b, c = ledger.run()
    assert ran == ["a", "b"], "the faulted check still runs"
    assert not a.regressed and a.value == "value of a"
    assert b.regressed and b.status == "REGRESSED" and b.error is None
    assert b.value == f"value of b {FAULT_MARK}" and FAULT_ENV in b.value
    assert not c.regressed and c.status == "not run"


def test_only_narrows_the_run_with_or_without_the_argument(monkeypatch):
    ran = _fakes(monkeypatch)
    monkeypatch.setenv(ONLY_ENV, "b,a")
    assert [o.claim.key for o in ledger.run()] == ["a", "b"]          # the ledger's order
    assert [o.claim.key for o in ledger.run(only=["b", "c"])] == ["b"]  # the claims in both
    monkeypatch.setenv(ONLY_ENV, " ")                                   # empty: unset
    assert [o.claim.key for o in ledger.run()] == ["a", "b", "c"]
    assert ran == ["a", "b", "b", "a", "b"]


@pytest.mark.parametrize("name", [FAULT_ENV, ONLY_ENV])
def test_an_unknown_key_is_refused_naming_the_variable(monkeypatch, name):
    ran = _fakes(monkeypatch)
    monkeypatch.setenv(name, "a,nope")
    with pytest.raises(ValueError, match=rf"{name}=a,nope: unknown claim 'nope'.*: a, b, c"):
        ledger.run()
    assert ran == [], "refused before any check ran"


def test_a_claim_without_a_check_cannot_be_faulted(monkeypatch):
    _fakes(monkeypatch)
    monkeypatch.setenv(FAULT_ENV, "c")
    with pytest.raises(ValueError, match=f"{FAULT_ENV}: claim 'c' is not checkable"):
        ledger.run()


def test_a_regression_is_red_for_the_book_and_plain_elsewhere(monkeypatch):
    _fakes(monkeypatch)
    monkeypatch.setenv(FAULT_ENV, "b")
    outcomes = ledger.run()
    assert regression_notice([outcomes[0], outcomes[2]]) == ""
    notice = regression_notice(outcomes)
    assert notice.startswith(":::{admonition} A claim regressed") and ":class: error" in notice
    assert f"* **Sec 2** (`b`, reproduced): ours: value of b {FAULT_MARK}" in notice
    broken = ledger.Outcome(outcomes[0].claim, "-", False, 0.1, error="RuntimeError: boom")
    two = regression_notice([broken, outcomes[1]])
    assert two.startswith(":::{admonition} 2 claims regressed")
    assert "ours: -; error: RuntimeError: boom" in two
    red = ledger.to_markdown(outcomes, summary=True, red_regressions=True)
    assert red.count("{bdg-danger}`REGRESSED`") == 1 and "| ok |" in red
    assert "{bdg-danger}`ERROR`: RuntimeError: boom" in ledger.to_markdown([broken],
                                                                           red_regressions=True)
    details = ledger.to_markdown_details(outcomes, red_regressions=True)
    assert details.count("{bdg-danger}`REGRESSED`") == 1
    for plain in (ledger.to_markdown(outcomes), ledger.to_markdown_details(outcomes)):
        assert "bdg-" not in plain and "REGRESSED" in plain


def test_reproduce_exits_1_on_the_injected_fault(tmp_path):
    env = {**os.environ, FAULT_ENV: "eq5-duality"}
    env.pop(ONLY_ENV, None)
    done = subprocess.run([str(Path(sys.executable).with_name("roughgp")), "reproduce",
                           "--only", "eq5-duality"], cwd=tmp_path, env=env,
                          capture_output=True, text=True, check=False)
    assert done.returncode == 1, done.stdout + done.stderr
    assert "REGRESSED (the verdict must be revisited): eq5-duality" in done.stderr
    assert "fault injected" in done.stdout + done.stderr


def test_reproduce_names_the_variable_of_an_unknown_key(monkeypatch, capsys):
    monkeypatch.setenv(FAULT_ENV, "fig99")
    assert main(["reproduce", "--only", "eq5-duality"]) == 2
    assert f"{FAULT_ENV}=fig99: unknown claim 'fig99'" in capsys.readouterr().err
