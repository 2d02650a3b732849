"""pytest: every chapter (``book/*.ipynb``) and every lab (``notebooks/*.ipynb``) is a test
item, run by nbmake (``pytest --nbmake``; ``make test`` passes it).

nbmake executes each notebook cell by cell; a failing cell (an assert of a claim among them)
fails the test with that cell and its traceback. Its run goes through the jupyter-cache that the
book build reads (:mod:`booktools.notebook_cache`): the notebooks run once for both, and a
notebook whose cells, library, lock and data are unchanged since its last successful run is not
run again (the progress line says "cached"). A fresh clone, as CI runs it, executes everything.

A notebook that ran without error but reports a regressed claim (the chapter "Claims ledger"
glues the list, hidden: :mod:`booktools.findings`) fails its item with the claims named, whether
it was executed now or its run (with its stored outputs) came from the cache: the book shows the
regression in red and builds every page, the tests fail on it. Likewise a notebook that shows a
figure or an output line wider than the book's column (:mod:`booktools.page_fit`).

What this file adds to nbmake: the marker ``notebook`` on each notebook item (``pytest -m "not
notebook"`` runs the unit tier alone), one BLAS thread per test process when several run, the
notebooks first and the longest first (dealt to xdist's workers), and one progress line per
notebook as it starts and ends.
"""

from __future__ import annotations

import os
import time

import pytest

from booktools import findings, notebook_cache, page_fit

# book/labs is a link to notebooks/ (so the book shows the labs): collect each lab once.
collect_ignore = ["book/labs"]


# With several test processes on few cores, each process (and each notebook's kernel, which
# inherits the environment) computes on one thread: two processes of two BLAS / OpenMP threads
# each on two cores run small factorisations many times slower than one thread would.
THREAD_VARIABLES = ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS")


def pytest_configure(config):
    worker = hasattr(config, "workerinput")
    if worker and int(config.workerinput.get("workercount", 1)) > 1:
        for name in THREAD_VARIABLES:
            os.environ.setdefault(name, "1")
    if not config.getoption("nbmake", False):
        return
    if not worker:  # the controller (or a run without xdist) only
        notebook_cache.prepare()
        config.pluginmanager.register(NotebookProgress(config), "roughgp-notebook-progress")
    _run_nbmake_through_the_cache()


def _is_notebook(item):
    return getattr(item, "nbmake", False)


_RUNS = {}  # notebook path -> notebook_cache.Executed, in this process


def _run_nbmake_through_the_cache():
    """nbmake's ``NotebookRun.execute`` (nbmake 1.5.5, pinned) taken through
    :func:`booktools.notebook_cache.execute`: from the cache when unchanged, stored in it when
    it passed; then failed when it reports a regressed claim (:mod:`booktools.findings`).
    nbmake's item, its options (``--nbmake-timeout``, ``--nbmake-kernel``)
    and its failure report are nbmake's own."""
    from nbmake.nb_run import NotebookRun

    nbmake_execute = NotebookRun.execute
    if getattr(nbmake_execute, "through_cache", False):
        return

    def execute(run):
        executed = notebook_cache.execute(run.filename, runner=lambda: nbmake_execute(run))
        _RUNS[str(executed.path)] = executed
        result = findings.fail_on_findings(executed.result, executed.path.name)
        return page_fit.fail_on_overflow(result, executed.path.name)

    execute.through_cache, execute.original = True, nbmake_execute
    NotebookRun.execute = execute


def pytest_itemcollected(item):
    if _is_notebook(item):
        item.add_marker(pytest.mark.notebook)


@pytest.hookimpl(hookwrapper=True)
def pytest_runtest_call(item):
    start = time.perf_counter()
    yield
    if _is_notebook(item):
        run = _RUNS.get(str(item.path.resolve()))
        if run is None:
            how = f"({time.perf_counter() - start:.0f} s)"
        else:
            how = f"{'cached' if run.cached else 'executed'} ({run.seconds:.0f} s)"
        item.user_properties.append(("notebook", how))


# Seconds each notebook took in CI (a fresh clone on the 2-core machine, two workers,
# 2026-12-05; lab9: its first run, beside another CI, 2026-12-08): only the order of the run
# depends on them. Others count as DEFAULT_SECONDS.
NOTEBOOK_SECONDS = {"claims": 293, "measured_surfaces": 221, "spurious_points": 175,
                    "posterior": 137, "model_ladder": 129, "lab8_measured_loop": 96,
                    "lab9_part_that_changes": 195,
                    "gp_model": 74, "model_check": 70, "ground": 52, "turned_profiles": 45,
                    "lab6_posterior": 42, "gap_filling": 37, "turned_surfaces": 37,
                    "honed": 32, "prescribed": 22, "non_gaussian": 12, "notation": 11,
                    "measurements": 8, "arma": 6, "lab5_fitting_profile": 6}
DEFAULT_SECONDS = 5


def _seconds(item):
    return NOTEBOOK_SECONDS.get(item.path.stem, DEFAULT_SECONDS)


def _shares(n_items, n_workers):
    """Where each worker's initial share of the items starts: xdist's work-stealing scheduler
    hands the first ``n // k`` items to the first worker, half of the rest to the next, ..."""
    starts, given = [], 0
    for left in range(n_workers, 0, -1):
        starts.append(given)
        given += (n_items - given) // left
    return starts


def pytest_collection_modifyitems(config, items):
    """The notebooks first, the longest first, and with several workers dealt out to the
    workers' shares of the run by longest processing time first (each notebook to the share
    with the least notebook time so far), so that the long notebooks do not queue behind each
    other on one worker while the other ends early. The unit tests fill the rest of each share
    and are stolen by whichever worker runs out first."""
    notebooks = sorted((i for i in items if _is_notebook(i)),
                       key=lambda i: (-_seconds(i), str(i.path)))
    units = [i for i in items if not _is_notebook(i)]
    workers = int(getattr(config, "workerinput", {}).get("workercount", 1))
    if workers <= 1 or len(notebooks) < 2:
        items[:] = notebooks + units
        return
    groups, load = [[] for _ in range(workers)], [0.0] * workers
    for item in notebooks:
        k = min(range(workers), key=lambda w: load[w])
        groups[k].append(item)
        load[k] += _seconds(item)
    starts, ordered, rest = _shares(len(items), workers), [], iter(units)
    for k, group in enumerate(groups):
        ordered.extend(group)
        end = starts[k + 1] if k + 1 < workers else len(items)
        while len(ordered) < end:
            ordered.append(next(rest))
    ordered.extend(rest)
    items[:] = ordered


class NotebookProgress:
    """One line per notebook as it starts and ends (the notebooks are what a person waits for),
    with xdist's workers as without them."""

    def __init__(self, config):
        self.config, self.total, self.done = config, None, 0

    def _say(self, text):
        terminal = self.config.pluginmanager.get_plugin("terminalreporter")
        if terminal is not None:
            if getattr(terminal._tw, "width_of_current_line", 0):  # after a row of dots
                terminal.write("\n")
            terminal.write_line(text)

    def pytest_collection_finish(self, session):
        if session.items:  # without xdist; under xdist the workers collect
            self.total = sum(_is_notebook(item) for item in session.items)

    def pytest_xdist_node_collection_finished(self, node, ids):
        self.total = sum(i.endswith(".ipynb") or ".ipynb::" in i for i in ids)

    def pytest_runtest_logstart(self, nodeid, location):
        if ".ipynb::" in nodeid:
            self._say(f"notebook {nodeid.split('::')[0]}: running ...")

    def pytest_runtest_logreport(self, report):
        if ".ipynb::" in report.nodeid and report.when == "call":
            self.done += 1
            how = dict(report.user_properties).get("notebook", "")
            self._say(f"notebook {report.nodeid.split('::')[0]}: {report.outcome} {how} "
                      f"[{self.done}/{self.total or '?'}]")
