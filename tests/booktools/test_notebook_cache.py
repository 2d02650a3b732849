"""The notebook cache shared by the tests and the book build (booktools/notebook_cache.py)."""

import nbformat

from booktools import notebook_cache


def _root(tmp_path):
    root = tmp_path / "repo"
    (root / "roughgp").mkdir(parents=True)
    (root / "roughgp" / "a.py").write_text("x = 1\n")
    (root / "data").mkdir()
    (root / "data" / "m.csv").write_text("1,2\n")
    (root / "requirements.lock").write_text("numpy==2.0\n")
    (root / "benchmarks" / "results").mkdir(parents=True)
    (root / "benchmarks" / "results" / "run.jsonl").write_text("{}\n")
    return root


def test_the_key_changes_with_the_library_the_data_the_records_the_lock_and_the_size_switch(
        tmp_path, monkeypatch):
    root = _root(tmp_path)
    monkeypatch.delenv("ROUGHGP_FULL", raising=False)
    key = notebook_cache.fingerprint(root)
    assert notebook_cache.fingerprint(root) == key
    (root / "roughgp" / "__pycache__").mkdir()
    (root / "roughgp" / "__pycache__" / "a.cpython-311.pyc").write_bytes(b"\0")
    assert notebook_cache.fingerprint(root) == key, "bytecode is not a dependency"
    keys = {key}
    for change in (lambda: (root / "roughgp" / "a.py").write_text("x = 2\n"),
                   lambda: (root / "roughgp" / "b.py").write_text(""),
                   lambda: (root / "data" / "m.csv").write_text("1,3\n"),
                   # a run recorded again: the chapters that report it must run again
                   lambda: (root / "benchmarks" / "results" / "run.jsonl").write_text("{1}\n"),
                   lambda: (root / "requirements.lock").write_text("numpy==2.1\n"),
                   lambda: monkeypatch.setenv("ROUGHGP_FULL", "1")):
        change()
        keys.add(notebook_cache.fingerprint(root))
    assert len(keys) == 7


def test_prepare_empties_a_cache_of_another_key_only(tmp_path):
    root, cache = _root(tmp_path), tmp_path / "cache"
    notebook_cache.prepare(cache, root, log=lambda m: None)
    (cache / "kept").write_text("")
    notebook_cache.prepare(cache, root, log=lambda m: None)
    assert (cache / "kept").exists()
    (root / "roughgp" / "a.py").write_text("x = 3\n")
    said = []
    notebook_cache.prepare(cache, root, log=said.append)
    assert not (cache / "kept").exists() and "runs again" in said[0]
    assert (cache / notebook_cache.KEY_FILE).read_text().strip() == notebook_cache.fingerprint(root)


def _notebook(path, *sources):
    nb = nbformat.v4.new_notebook()
    nb.metadata["kernelspec"] = {"name": "python3", "display_name": "Python 3",
                                 "language": "python"}
    nb.cells = [nbformat.v4.new_code_cell(s) for s in sources]
    nbformat.write(nb, path)
    return path


def test_a_notebook_runs_once_then_comes_from_the_cache(tmp_path):
    cache = notebook_cache.prepare(tmp_path / "cache", _root(tmp_path), log=lambda m: None)
    path = _notebook(tmp_path / "ok.ipynb", "from pathlib import Path",
                     "Path('ran').open('a').write('x')")
    first = notebook_cache.execute(path, cache)
    assert not first.cached and first.error is None
    assert (tmp_path / "ran").read_text() == "x", "it ran in its own folder"
    second = notebook_cache.execute(path, cache)
    assert second.cached and second.error is None
    assert (tmp_path / "ran").read_text() == "x", "the cached run did not execute"
    _notebook(path, "from pathlib import Path", "Path('ran').open('a').write('y')")
    assert not notebook_cache.execute(path, cache).cached, "a changed cell runs again"


def test_a_failing_cell_fails_with_its_traceback_and_is_not_cached(tmp_path):
    cache = notebook_cache.prepare(tmp_path / "cache", _root(tmp_path), log=lambda m: None)
    path = _notebook(tmp_path / "bad.ipynb", "x = 1", "assert x == 2, 'the claim fails'")
    for _ in range(2):
        run = notebook_cache.execute(path, cache)
        assert not run.cached and "the claim fails" in run.error


def test_the_kernels_share_results_inside_the_cache_and_the_test_process_does_not(
        tmp_path, monkeypatch):
    from roughgp.common.results_cache import ENV

    monkeypatch.delenv(ENV, raising=False)
    cache = notebook_cache.prepare(tmp_path / "cache", _root(tmp_path), log=lambda m: None)
    path = _notebook(tmp_path / "env.ipynb", "import os",
                     f"assert os.environ[{ENV!r}] == {str(cache / 'results')!r}")
    assert notebook_cache.execute(path, cache).error is None
    assert ENV not in __import__("os").environ          # restored after the kernel ran


def test_cache_writes_are_serialised(tmp_path):
    """Two writers never prune each other's fresh record: cache_notebook_bundle runs under one
    exclusive lock (a second process cannot take it while the first holds it)."""
    import subprocess
    import sys

    from booktools.notebook_cache import _writing

    probe = ("import fcntl, sys; h = open(sys.argv[1], 'a'); "
             "fcntl.flock(h, fcntl.LOCK_EX | fcntl.LOCK_NB)")
    with _writing(tmp_path):
        held = subprocess.run([sys.executable, "-c", probe, str(tmp_path / "write.lock")])
    free = subprocess.run([sys.executable, "-c", probe, str(tmp_path / "write.lock")])
    assert held.returncode != 0 and free.returncode == 0
