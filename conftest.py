"""pytest: every chapter (``book/*.ipynb``) and every lab (``book/labs/*.ipynb``) is a test item.

Each notebook is executed cell by cell (a failing cell, an assert of a claim among them, fails
the test with its traceback) through the jupyter-cache that the book build reads
(:mod:`booktools.notebook_cache`): the notebooks run once for both, and a notebook whose cells,
library, lock and data are unchanged since its last successful run is not run again (the test
says "cached"). ``make test`` on a fresh clone, as CI runs it, executes everything.

Each notebook item carries the marker ``notebook``: ``pytest -m "not notebook"`` runs the unit
tier alone.
"""

from __future__ import annotations

import os

import pytest

from booktools import notebook_cache


# With several test processes on few cores, each process (and each notebook's kernel, which
# inherits the environment) computes on one thread: two processes of two BLAS / OpenMP threads
# each on two cores run small factorisations many times slower than one thread would.
THREAD_VARIABLES = ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS")


def pytest_configure(config):
    if not hasattr(config, "workerinput"):  # the controller (or a run without xdist) only
        notebook_cache.prepare()
        config.pluginmanager.register(NotebookProgress(config), "roughgp-notebook-progress")
    elif int(config.workerinput.get("workercount", 1)) > 1:
        for name in THREAD_VARIABLES:
            os.environ.setdefault(name, "1")


# Seconds each notebook took in CI (a fresh clone on the 2-core machine, two workers,
# 2026-12-02): only the order of the run depends on them. Others count as DEFAULT_SECONDS.
NOTEBOOK_SECONDS = {"claims": 236, "measured_surfaces": 225, "posterior": 152, "gp_model": 111,
                    "gap_filling": 54, "turned_profiles": 52, "ground": 49, "honed": 39,
                    "lab6_posterior": 32, "prescribed": 25, "non_gaussian": 15,
                    "measurements": 14, "notation": 11, "turned_surfaces": 10}
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
    notebooks = sorted((i for i in items if isinstance(i, NotebookItem)),
                       key=lambda i: (-_seconds(i), str(i.path)))
    units = [i for i in items if not isinstance(i, NotebookItem)]
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
            self.total = sum(isinstance(item, NotebookItem) for item in session.items)

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


def pytest_collect_file(file_path, parent):
    if file_path.suffix == ".ipynb" and ".ipynb_checkpoints" not in file_path.parts \
            and "_build" not in file_path.parts:
        return NotebookFile.from_parent(parent, path=file_path)
    return None


class NotebookFile(pytest.File):
    def collect(self):
        yield NotebookItem.from_parent(self, name=self.path.name)


class NotebookFailed(Exception):
    pass


class NotebookItem(pytest.Item):
    def __init__(self, **kwargs):
        super().__init__(**kwargs)
        self.add_marker(pytest.mark.notebook)

    def runtest(self):
        run = notebook_cache.execute(self.path)
        how = "cached" if run.cached else "executed"
        self.user_properties.append(("notebook", f"{how} ({run.seconds:.0f} s)"))
        if run.cached:
            self.add_report_section("call", "notebook", f"taken from the cache: its cells, "
                                    f"roughgp, the lock and the data are unchanged since it "
                                    f"passed in {run.seconds:.0f} s")
        if run.error is not None:
            raise NotebookFailed(run.error)

    def repr_failure(self, excinfo, style=None):
        if isinstance(excinfo.value, NotebookFailed):
            return f"{self.path.name}: a cell failed\n{excinfo.value}"
        return super().repr_failure(excinfo, style)

    def reportinfo(self):
        return self.path, 0, f"notebook {self.path.relative_to(self.config.rootpath)}"
