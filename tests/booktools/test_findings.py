"""A regressed claim fails the notebook's test item (booktools/findings.py, through conftest.py),
executed or from the notebook cache, and the ledger's test switches are part of the cache's key
(booktools/notebook_cache.py)."""

import nbformat
from nbmake.nb_result import NotebookError, NotebookResult

from booktools import findings, notebook_cache
from tests.booktools.test_notebook_cache import _notebook


def _glue_output(name, text, shown=False):
    prefix = "" if shown else findings.GLUE_PREFIX
    return nbformat.v4.new_output(
        "display_data", data={prefix + "text/plain": text},
        metadata={"scrapbook": {"name": name, "mime_prefix": prefix}})


def _executed(*outputs):
    nb = nbformat.v4.new_notebook()
    nb.cells = [nbformat.v4.new_markdown_cell("# a chapter"), nbformat.v4.new_code_cell("x = 1"),
                nbformat.v4.new_code_cell("glue(...)")]
    nb.cells[2].outputs = list(outputs)
    return nb


def test_the_glued_list_is_read_back():
    nb = _executed(_glue_output("other", "3"),
                   _glue_output(findings.REGRESSED, "['eq5-duality: 2.5e-05', \"fig1: it's\"]"))
    assert findings.glued(nb, "other") == 3
    assert findings.glued(nb, "missing") is None
    assert findings.regressed_claims(nb) == ["eq5-duality: 2.5e-05", "fig1: it's"]
    assert findings.regressed_claims(_executed()) == []
    assert findings.regressed_claims(_executed(_glue_output(findings.REGRESSED, "[]"))) == []


def test_a_regressed_claim_fails_the_result_naming_it():
    nb = _executed(_glue_output(findings.REGRESSED, "['eq5-duality: 2.5e-05 [fault]']"))
    failed = findings.fail_on_findings(NotebookResult(nb, None), "claims.ipynb")
    assert failed.error.summary == "claims.ipynb: 1 regressed claim(s): eq5-duality"
    assert "  eq5-duality: 2.5e-05 [fault]" in failed.error.trace
    assert failed.error.failing_cell_index == 2 and failed.nb is nb
    clean = NotebookResult(_executed(_glue_output(findings.REGRESSED, "[]")), None)
    assert findings.fail_on_findings(clean) is clean
    error = NotebookError("boom", "Traceback ...", 1)
    broken = NotebookResult(nb, error)
    assert findings.fail_on_findings(broken).error is error, "a failing cell is reported as is"


def test_a_regression_fails_again_when_its_run_comes_from_the_cache(tmp_path):
    """The run passed nbmake (no cell raised), so it is stored; the next run takes it from the
    cache with its outputs, and fails the same way: no silent pass."""
    cache = notebook_cache.prepare(tmp_path / "cache", log=lambda m: None)
    path = _notebook(tmp_path / "claims.ipynb", "from myst_nb import glue",
                     "glue('regressed_claims', ['k: 1.5'], display=False)")
    for cached in (False, True):
        run = notebook_cache.execute(path, cache)
        assert run.cached is cached and run.error is None
        assert run.result.nb.cells[1].outputs, "the stored outputs come back"
        failed = findings.fail_on_findings(run.result, path.name)
        assert failed.error is not None and failed.error.summary.endswith("claim(s): k")


def test_the_ledger_switches_are_part_of_the_cache_key_when_set(monkeypatch, tmp_path):
    """A run on a few claims, with a fault injected or under jittered starts, never stands in
    for the real one."""
    (tmp_path / "roughgp").mkdir()
    (tmp_path / "roughgp" / "a.py").write_text("x = 1\n")
    for name in notebook_cache.LEDGER_SWITCHES:
        monkeypatch.delenv(name, raising=False)
    key = notebook_cache.fingerprint(tmp_path)
    monkeypatch.setenv("ROUGHGP_LEDGER_ONLY", "")
    assert notebook_cache.fingerprint(tmp_path) == key, "empty is unset"
    keys = {key}
    for name in notebook_cache.LEDGER_SWITCHES:
        monkeypatch.setenv(name, "eq5-duality")
        keys.add(notebook_cache.fingerprint(tmp_path))
    assert len(keys) == 4
    from roughgp.common.numerics import ENV as JITTER_ENV
    from roughgp.ledger.runner import FAULT_ENV, ONLY_ENV
    assert set(notebook_cache.LEDGER_SWITCHES) == {FAULT_ENV, ONLY_ENV, JITTER_ENV}
