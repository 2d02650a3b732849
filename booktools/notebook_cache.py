"""One execution per notebook: the jupyter-cache that the tests and the book build share.

The book is built by myst-nb with ``execute_notebooks: cache``: a chapter whose code cells are
unchanged since its last successful run is taken from ``book/_build/.jupyter_cache`` instead of
being executed again. The tests (``make test``, ``pytest --nbmake``) execute every chapter and
lab with nbmake, and ``conftest.py`` routes nbmake's run through :func:`execute`: a notebook
found in the cache is not run again, and one that nbmake ran without error is stored there with
its outputs (jupyter-cache keeps a notebook's existing outputs). So a ``make book`` after
``make test`` executes nothing, and a second ``make book`` with nothing changed only renders.

jupyter-cache keys a notebook by its code cells alone; the book's notebooks also depend on the
library, the pinned environment, the data they read and the size switch. :func:`fingerprint`
hashes those, and :func:`prepare` empties the cache when the fingerprint changed, so a change to
``roughgp/``, to ``benchmarks/results/`` (the recorded runs the chapters read), to
``requirements.lock``, to ``pyproject.toml``, to ``data/`` or to
``ROUGHGP_FULL`` re-executes every chapter. A fresh clone has no cache: everything runs. The
ledger's test switches ``ROUGHGP_LEDGER_ONLY`` and ``ROUGHGP_LEDGER_FAULT`` (a run on a few
claims, an injected regression) and the start jitter ``ROUGHGP_START_JITTER`` (a perturbed
numerical set-up) are part of the fingerprint when set, so such a run never stands in for the
real one in the book.

A notebook that ran without error is stored even when what it reports must fail the tests (a
regressed claim: :mod:`booktools.findings`); :func:`execute` gives a cached run back with its
stored outputs, so the tests read that report from the cached run as from a fresh one.

Expensive experiment results that several notebooks compute (the careful fits of figure 7,
the bullet land's fit and check) are shared through ``roughgp.common.results_cache``: the
kernels started here get ``ROUGHGP_RESULTS_CACHE`` = ``<cache>/results``, a folder inside the
cache, emptied with it.

As a Sphinx extension (``sphinx.local_extensions`` in ``book/_config.yml``) :func:`setup` runs
:func:`prepare` before myst-nb opens the cache, so ``jupyter-book build book/`` is safe on its
own as well, and makes Sphinx re-read every notebook when the fingerprint changed since the last
build (Sphinx re-reads only the pages whose own source changed).
"""

from __future__ import annotations

import contextlib
import hashlib
import os
import platform
import shutil
import sys
import time
from dataclasses import dataclass
from pathlib import Path

from roughgp.common.digests import source_files, update_with_files
from roughgp.common.settings import full_size

ROOT = Path(__file__).resolve().parents[1]
BOOK = ROOT / "book"
CACHE = BOOK / "_build" / ".jupyter_cache"
KEY_FILE = "roughgp-fingerprint.txt"
# What every chapter depends on besides its own cells (paths relative to the repository).
#: what the notebooks read besides their cells: the library, the data, the recorded runs that
#: the chapters report (a run recorded again must re-execute them), the pinned environment
DEPENDENCIES = ("roughgp", "data", "benchmarks/results", "requirements.lock", "pyproject.toml")
TIMEOUT = 900  # seconds per cell, as book/_config.yml's execute.timeout
# Test switches of the claims ledger (roughgp.ledger.runner.ONLY_ENV and FAULT_ENV) and the start
# jitter of a perturbed numerical set-up (roughgp.common.numerics.ENV): part of the fingerprint
# when set (not imported from there: that would load every check in each process).
LEDGER_SWITCHES = ("ROUGHGP_LEDGER_ONLY", "ROUGHGP_LEDGER_FAULT", "ROUGHGP_START_JITTER")

__all__ = ["CACHE", "Executed", "execute", "fingerprint", "prepare", "results_folder", "setup"]


def _files(root: Path):
    for name in DEPENDENCIES:
        yield from source_files(root / name)


def fingerprint(root: Path = ROOT) -> str:
    """SHA-256 over what the notebooks depend on: the files of :data:`DEPENDENCIES` (names and
    contents), the Python and torch versions, the ``ROUGHGP_FULL`` switch, and those of
    :data:`LEDGER_SWITCHES` that are set (unset, the key is what it was before they existed)."""
    h = hashlib.sha256()
    update_with_files(h, _files(root), root)
    try:
        from importlib.metadata import version
        torch = version("torch")
    except Exception:  # noqa: BLE001 - not installed: part of the key as such
        torch = "none"
    h.update(f"python {platform.python_version()} torch {torch} full {full_size()}".encode())
    for name in LEDGER_SWITCHES:
        if os.environ.get(name, "").strip():
            h.update(f"\0{name}={os.environ[name].strip()}".encode())
    return h.hexdigest()


def prepare(cache: Path = CACHE, root: Path = ROOT, log=print) -> Path:
    """Empty ``cache`` if it was filled under another :func:`fingerprint`; create it (and its
    database) if missing. Returns ``cache``."""
    cache = Path(cache)
    key = fingerprint(root)
    key_file = cache / KEY_FILE
    if cache.exists() and (not key_file.is_file() or key_file.read_text().strip() != key):
        log(f"notebook cache: roughgp, the lock, the data, the recorded runs, ROUGHGP_FULL or a "
            f"ledger test switch changed; every notebook runs again (emptied {cache})")
        shutil.rmtree(cache)
    cache.mkdir(parents=True, exist_ok=True)
    key_file.write_text(key + "\n")
    from jupyter_cache import get_cache
    get_cache(str(cache)).list_cache_records()  # creates the database once, before any worker
    return cache


def results_folder(cache: Path = CACHE) -> Path:
    """The folder ``results`` inside ``cache`` (emptied with the cache by :func:`prepare`):
    what ``ROUGHGP_RESULTS_CACHE`` names for the kernels of the book's notebooks."""
    folder = Path(cache) / "results"
    folder.mkdir(parents=True, exist_ok=True)
    return folder


@contextlib.contextmanager
def _sharing_results(cache):
    """``ROUGHGP_RESULTS_CACHE`` set for the kernels started inside, restored after (the
    test process itself keeps computing everything)."""
    from roughgp.common.results_cache import ENV

    before = os.environ.get(ENV)
    os.environ[ENV] = str(results_folder(cache))
    try:
        yield
    finally:
        if before is None:
            os.environ.pop(ENV, None)
        else:
            os.environ[ENV] = before


@dataclass
class Executed:
    """A notebook's run: ``cached`` (taken from the cache), ``seconds`` (its execution time,
    as recorded when it ran), ``error`` (the failing cell's source and traceback, or None),
    ``result`` (nbmake's ``NotebookResult``: the notebook with its outputs, and the error)."""

    path: Path
    cached: bool
    seconds: float
    error: str | None = None
    result: object = None


def _with_outputs(source, executed):
    """``source`` with the outputs and execution counts of ``executed`` (the same cells, run):
    the notebook jupyter-cache stores, hashed on the source's own metadata as myst-nb hashes
    it when it looks a notebook up."""
    import copy

    notebook = copy.deepcopy(source)
    for cell, ran in zip(notebook.cells, executed.cells):
        if cell.cell_type == "code":
            cell.outputs = ran.get("outputs", [])
            cell.execution_count = ran.get("execution_count")
    return notebook


def execute(path: str | Path, cache: Path = CACHE, timeout: int = TIMEOUT,
            runner=None) -> Executed:
    """Take ``path``'s outputs from the cache, or execute it with nbmake (in its own folder, as
    the book build does) and cache it if every cell ran, so that the book build (myst-nb's
    cache mode) finds the result and executes nothing. A cached run's ``result.nb`` is the
    notebook with its stored outputs.

    ``runner``: a callable returning nbmake's ``NotebookResult`` for ``path`` (the test run
    passes nbmake's own, with its options); by default ``NotebookRun(path, timeout)``."""
    import nbformat
    from jupyter_cache import get_cache
    from jupyter_cache.base import CacheBundleIn
    from nbmake.nb_result import NotebookResult
    from nbmake.nb_run import NotebookRun

    path = Path(path).resolve()
    store = get_cache(str(cache))
    notebook = nbformat.read(path, as_version=4)
    try:
        pk, stored = store.merge_match_into_notebook(notebook)   # with the stored outputs
        record = store.get_cache_record(pk)
        return Executed(path, True, float(record.data.get("execution_seconds") or 0.0),
                        result=NotebookResult(nb=stored, error=None))
    except KeyError:
        pass
    if runner is None:
        # nbmake's own run, also where conftest.py has routed it through this function
        nbmake_execute = getattr(NotebookRun.execute, "original", NotebookRun.execute)

        def runner():
            return nbmake_execute(NotebookRun(path, timeout))
    start = time.perf_counter()
    with _sharing_results(cache):
        result = runner()
    seconds = time.perf_counter() - start
    if result.error is not None:
        return Executed(path, False, seconds, result.error.trace, result)
    with _writing(cache):
        store.cache_notebook_bundle(CacheBundleIn(_with_outputs(notebook, result.nb), str(path),
                                                  data={"execution_seconds": seconds}),
                                    check_validity=False, overwrite=True)
    return Executed(path, False, seconds, result=result)


@contextlib.contextmanager
def _writing(cache):
    """One writer at a time (an exclusive lock on ``cache/write.lock``): jupyter-cache's
    ``cache_notebook_bundle`` ends by pruning old records with two separate queries, so a record
    that another test process inserts between them counts as old and is removed before its
    notebook file is written ("Notebook file does not exist for cache record PK", seen once
    with two test processes; jupyter-cache 1.0.1)."""
    import fcntl

    with open(Path(cache) / "write.lock", "a") as handle:
        fcntl.flock(handle, fcntl.LOCK_EX)
        try:
            yield
        finally:
            fcntl.flock(handle, fcntl.LOCK_UN)


def setup(app):
    """Sphinx extension: :func:`prepare` the cache myst-nb is about to open, and re-read every
    notebook when the fingerprint differs from the one of the last build (Sphinx itself only
    re-reads the pages whose source changed; a notebook's outputs also change with roughgp)."""
    def _prepare(app, config):
        path = config.nb_execution_cache_path or Path(app.outdir).parent / ".jupyter_cache"
        from roughgp.common.results_cache import ENV

        cache = prepare(Path(path).resolve(), log=lambda msg: print(msg, file=sys.stderr))
        os.environ[ENV] = str(results_folder(cache))   # for the kernels myst-nb starts

    def _outdated(app, env, added, changed, removed):
        key, old = fingerprint(), getattr(env, "roughgp_notebook_key", None)
        env.roughgp_notebook_key = key
        if old is None or old == key:
            return []
        return [doc for doc in env.found_docs
                if str(env.doc2path(doc)).endswith(".ipynb") and doc not in added]

    app.connect("config-inited", _prepare, priority=400)
    app.connect("env-get-outdated", _outdated)
    return {"parallel_read_safe": False, "parallel_write_safe": True}
