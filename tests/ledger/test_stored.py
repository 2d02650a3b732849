"""A saved run of the ledger (roughgp.ledger.stored) and ``roughgp reproduce --reuse``."""

import json

import pytest

from roughgp import ledger
from roughgp.cli.main import main
from roughgp.ledger import stored


def _outcomes(regressed=()):
    """One outcome per claim, without running a check (the values are placeholders)."""
    return [ledger.Outcome(c, "value of " + c.key, c.key not in regressed, 0.5)
            for c in ledger.CLAIMS]


def test_a_saved_complete_run_comes_back(tmp_path):
    stored.save(_outcomes(), tmp_path, full=False)
    outcomes, why = stored.load(tmp_path, full=False)
    assert [o.claim.key for o in outcomes] == ledger.claim_keys() and "the run of" in why
    assert [o.value for o in outcomes] == [o.value for o in _outcomes()]
    assert not any(o.regressed for o in outcomes if o.claim.check is not None)


def test_a_run_is_not_reused_at_other_sizes_after_a_change_or_when_incomplete(
        tmp_path, monkeypatch):
    assert stored.load(tmp_path, full=False) == (None, f"no saved run in {tmp_path}")
    stored.save(_outcomes(), tmp_path, full=False)
    outcomes, why = stored.load(tmp_path, full=True)
    assert outcomes is None and "quick sizes" in why
    monkeypatch.setattr(stored, "fingerprint", lambda full: "something else")
    outcomes, why = stored.load(tmp_path, full=False)
    assert outcomes is None and "changed" in why
    monkeypatch.undo()
    stored.save(_outcomes()[:-1], tmp_path, full=False)
    outcomes, why = stored.load(tmp_path, full=False)
    assert outcomes is None and "every claim" in why
    (tmp_path / "ledger.json").write_text("{not json")
    assert "unreadable" in stored.load(tmp_path, full=False)[1]


def test_the_fingerprint_follows_the_size_setting():
    assert stored.fingerprint(False) == stored.fingerprint(False) != stored.fingerprint(True)


def _no_checks(**kwargs):
    raise AssertionError("--reuse ran the checks although the saved run was reusable")


def test_reproduce_reuse_reports_the_saved_run_without_computing(capsys, tmp_path, monkeypatch):
    key = ledger.claim_keys()[3]
    stored.save(_outcomes(regressed={key}), tmp_path, full=False)
    monkeypatch.setattr(ledger, "run", _no_checks)
    code = main(["reproduce", "--out", str(tmp_path), "--reuse"])
    out, err = capsys.readouterr()
    assert code == 1 and "reusing the run of" in err and f"REGRESSED" in out and key in err
    stored.save(_outcomes(), tmp_path, full=False)
    assert main(["reproduce", "--out", str(tmp_path), "--reuse", "--only", key]) == 0
    out, _ = capsys.readouterr()
    assert key in out and "1 claim(s)" in out


def test_reproduce_reuse_runs_when_the_saved_run_is_stale(capsys, tmp_path, monkeypatch):
    stored.save(_outcomes(), tmp_path, full=False)
    run = json.loads((tmp_path / stored.RUN_FILE).read_text())
    (tmp_path / stored.RUN_FILE).write_text(json.dumps(dict(run, fingerprint="old")))
    c = ledger.claim("eq5-duality")
    monkeypatch.setattr(ledger, "run", lambda **kw: [ledger.Outcome(c, "ran", True, 0.1)])
    assert main(["reproduce", "--out", str(tmp_path), "--reuse", "--only", c.key]) == 0
    out, err = capsys.readouterr()
    assert "changed since the saved run; running the checks" in err and "ran" in out
    assert not (tmp_path / stored.RUN_FILE).exists(), "a partial run is not saved for reuse"


def test_reuse_needs_out(capsys):
    assert main(["reproduce", "--reuse"]) == 2
    assert "--reuse needs --out" in capsys.readouterr().err


def test_a_saved_run_records_its_numerical_setup(tmp_path, monkeypatch):
    monkeypatch.setenv("ROUGHGP_START_JITTER", "5")
    stored.save(_outcomes(), tmp_path, full=False)
    setup = stored.saved_setup(tmp_path)
    assert setup["start_jitter"] == 5 and setup["blas_threads"] >= 1
    assert stored.saved_setup(tmp_path / "nowhere") is None


def test_reproduce_setups_fails_on_a_verdict_that_moves_with_the_setup(capsys, tmp_path,
                                                                       monkeypatch):
    """--setups reuses the saved run for the set-up it recorded, runs the others (faked here)
    and exits 1 naming the claim whose verdict differs; it writes the table beside the run."""
    from roughgp.ledger import setups

    monkeypatch.setenv("ROUGHGP_START_JITTER", "0")
    stored.save(_outcomes(), tmp_path, full=False)
    here = setups.Setup(**stored.saved_setup(tmp_path))
    seen = {}

    def fake_run_setups(keys, all_setups, *, full, reuse, progress):
        seen.update(keys=keys, reuse=reuse)
        runs = []
        for s in all_setups:
            if s in reuse:
                runs.append(setups.SetupRun(s, reuse[s], 1.0, reused=True))
            else:
                flip = s.start_jitter == 1
                runs.append(setups.SetupRun(s, [ledger.Outcome(ledger.claim(k), "moved",
                                                               not (flip and k == "fig7-cause"),
                                                               0.1) for k in keys], 2.0))
        return runs

    monkeypatch.setattr(setups, "run_setups", fake_run_setups)
    code = main(["reproduce", "--out", str(tmp_path), "--reuse", "--setups"])
    out, err = capsys.readouterr()
    assert code == 1 and "DEPEND ON THE NUMERICAL SET-UP" in err and "fig7-cause:" in err
    assert seen["keys"] == setups.search_keys() and list(seen["reuse"]) == [here]
    assert "1 verdict(s) differ" in out
    assert "REGRESSED: moved" in (tmp_path / "setups.md").read_text()
    assert len(json.loads((tmp_path / "setups.json").read_text())) == len(setups.SETUPS)
