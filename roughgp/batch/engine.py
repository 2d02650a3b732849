"""The batch engine: measurement files run through a :class:`~roughgp.batch.records.Plan` on a
Dask cluster (``dask.distributed``), each file's record written as it ends, one table at the end
(:func:`run_batch`), on :func:`run_cases`, which runs any independent seeded cases on the same
cluster (the project's long benchmarks: ``benchmarks/model_check_calibration.py``).

* The cluster: by default a ``LocalCluster`` of ``workers`` processes (default: the machine's
  cores), one thread each, with the BLAS libraries limited to one thread per worker (the
  environment of each worker process: ``OMP_NUM_THREADS``, ``OPENBLAS_NUM_THREADS``,
  ``MKL_NUM_THREADS`` = 1; and each file runs inside
  :func:`roughgp.common.threads.one_blas_thread`), so that the workers do not fight over the
  cores; or, with ``scheduler``, an existing cluster (``dask scheduler`` / ``dask worker``)
  whose workers see the same files and output folder (a shared file system).
* The numbers do not depend on the workers: each file's seed is
  :func:`~roughgp.batch.records.file_seed` (the user's seed and the file's SHA-256) and each
  file runs alone in its worker.
* Loss-free and resumable: the output folder holds ``records/NAME.json`` (one per file, written
  atomically by this process as the file's result arrives), ``files/NAME/`` (its artefacts,
  written atomically by the worker) and the table (``table.csv``, ``table.parquet``). A rerun
  skips the files whose record is complete and current
  (:func:`~roughgp.batch.records.current_record`); an interrupted batch (Ctrl-C) leaves only
  complete records. A file whose step fails has its error in its record and row; the others go
  on.
"""

from __future__ import annotations

import dataclasses
import glob
import itertools
import json
import logging
import os
import time
from pathlib import Path

from roughgp.batch.records import Plan, current_record, record_name, write_record
from roughgp.batch.table import write_table
from roughgp.common.digests import file_sha256

__all__ = ["expand_inputs", "BatchResult", "run_batch", "run_cases", "on_one_thread", "BLAS_ENV",
           "default_workers", "NOT_MEASUREMENTS", "add_cluster_options", "appending_records"]

#: the environment of each local worker process: one BLAS / OpenMP thread
BLAS_ENV = {"OMP_NUM_THREADS": "1", "OPENBLAS_NUM_THREADS": "1", "MKL_NUM_THREADS": "1"}

#: in a folder, files with these endings or names starting so are no measurements and are left
#: out (given by name or glob they are read, and fail in their row if they are no measurement)
NOT_MEASUREMENTS = ((".md", ".json", ".png", ".pdf", ".svg", ".html", ".py", ".ipynb",
                     ".yml", ".yaml", ".parquet", ".partial"), ("LICENSE", "README", "COPYING"))


def default_workers() -> int:
    """The cores this process may use (``os.sched_getaffinity``), at least 1."""
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except AttributeError:  # pragma: no cover - not Linux
        return max(1, os.cpu_count() or 1)


def _inside(path: Path, folder: Path | None) -> bool:
    if folder is None:
        return False
    try:
        path.resolve().relative_to(folder.resolve())
        return True
    except ValueError:
        return False


def expand_inputs(specs, exclude=None) -> list[Path]:
    """The files named by ``specs``: files, globs (``data/*.x3p``, ``**`` recursive) and
    folders (their files, not their subfolders', without hidden files and
    :data:`NOT_MEASUREMENTS`), each once, sorted by path; none inside the folder ``exclude``
    (the batch's output folder, whose artefacts are no inputs)."""
    exclude = None if exclude is None else Path(exclude)
    found = {}
    for spec in specs:
        spec = str(spec)
        path = Path(spec)
        if path.is_dir():
            suffixes, prefixes = NOT_MEASUREMENTS
            candidates = [p for p in sorted(path.iterdir()) if p.is_file()
                          and not p.name.startswith(".")
                          and not p.name.lower().endswith(suffixes)
                          and not p.name.upper().startswith(prefixes)]
        elif path.is_file():
            candidates = [path]
        else:
            candidates = [Path(p) for p in sorted(glob.glob(spec, recursive=True))
                          if Path(p).is_file()]
        for candidate in candidates:
            if _inside(candidate, exclude):
                continue
            found.setdefault(os.path.abspath(candidate), candidate)
    return sorted(found.values(), key=lambda p: str(p))


@dataclasses.dataclass
class BatchResult:
    """What :func:`run_batch` did: the records in the order of the files, how many were run
    and skipped (current records reused), how many failed, the table files written, and the
    Dask dashboard's address (None for a local cluster without one)."""

    records: list
    ran: int
    skipped: int
    failed: int
    tables: list
    dashboard: str | None = None

    @property
    def failed_files(self) -> list:
        return [r["path"] for r in self.records if r.get("status") != "done"]


def _task(path, sha256, plan, folder):
    """One file on a worker (:func:`roughgp.batch.steps.run_file`)."""
    from roughgp.batch.steps import run_file
    return run_file(path, sha256, plan, folder)


def _client(workers, scheduler):
    """``(client, cluster)``: a client of the scheduler at ``scheduler``, or of a new
    ``LocalCluster`` of ``workers`` single-threaded worker processes (BLAS on one thread)."""
    from distributed import Client, LocalCluster
    if scheduler is not None:
        return Client(scheduler, timeout="30s"), None
    cluster = LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                           dashboard_address=":0", silence_logs=logging.ERROR, env=BLAS_ENV)
    return Client(cluster), cluster


def run_cases(function, cases, *, workers=None, scheduler=None, client=None, started=None,
              on_result=None) -> None:
    """Run ``function(*args)`` for each ``(key, args, name)`` of ``cases`` on a Dask cluster and
    call ``on_result(key, result)`` in this process as each ends, in the order they end
    (``result`` is the exception where the call raised or its worker was lost). The engine of
    :func:`run_batch`, and of any long run made of independent cases (a benchmark's seeded
    cases: what a case computes must depend on its arguments only, never on the order or the
    worker, so that the records are the same with any number of workers).

    The cluster: ``client`` (an existing ``distributed.Client``, kept open), else the scheduler
    at ``scheduler``, else a new ``LocalCluster`` of ``workers`` single-threaded processes
    (default :func:`default_workers`; BLAS on one thread), closed at the end. ``name``: the
    task's key in Dask (unique). ``started``: called with the dashboard's address (None for a
    local cluster) and the number of workers once the cluster is up. A KeyboardInterrupt ends
    the run at once (the cluster closed); what ``on_result`` wrote stays.
    """
    cases = list(cases)
    if not cases:
        return
    own = client is None
    cluster = None
    if own:
        client, cluster = _client(workers or default_workers(), scheduler)
    try:
        from distributed import as_completed
        link = getattr(client, "dashboard_link", None) if (scheduler or not own) else None
        n_workers = max(1, len(client.scheduler_info().get("workers", {})))
        if started is not None:
            started(link, n_workers)
        futures = {client.submit(function, *args, key=name, pure=False): key
                   for key, args, name in cases}
        for future in as_completed(futures):
            try:
                result = future.result()
            except Exception as exc:  # noqa: BLE001 - handed to on_result
                result = exc
            if on_result is not None:
                on_result(futures[future], result)
    finally:
        if own:
            client.close()
            if cluster is not None:
                cluster.close()


def on_one_thread(function, *args):
    """``function(*args)`` with the BLAS libraries on one thread and its warnings silenced: a
    long run's case on a worker of :func:`run_cases` (``run_cases(on_one_thread, [(key,
    (function, *args), name), ...])``; the record is what counts)."""
    import warnings

    from threadpoolctl import threadpool_limits
    with threadpool_limits(1), warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return function(*args)


def add_cluster_options(parser) -> None:
    """``--workers N`` and ``--scheduler ADDRESS``, the cluster of :func:`run_cases`, on an
    ``argparse`` parser (the benchmark scripts' long runs)."""
    parser.add_argument("--workers", type=int, default=None,
                        help="local worker processes (default: the cores)")
    parser.add_argument("--scheduler", default=None,
                        help="the address of an existing Dask scheduler (instead of --workers)")


def appending_records(path, describe, total):
    """An ``on_result`` for :func:`run_cases` that appends each case's record (a JSON-able
    dict) to the JSON-lines file ``path`` as it ends, so that an interrupted run keeps what it
    finished, and prints ``[i/total] key: describe(record)``; a case that failed is printed,
    not recorded (a rerun runs it again)."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    count = itertools.count(1)

    def record(key, result):
        if isinstance(result, BaseException):
            print(f"{key}: failed: {result!r}", flush=True)
            return
        with open(path, "a", encoding="utf-8") as handle:
            handle.write(json.dumps(result) + "\n")
        print(f"[{next(count)}/{total}] {key}: {describe(result)}", flush=True)

    return record


def run_batch(files, plan: Plan, out, *, workers=None, scheduler=None, progress=None,
              client=None, started=None) -> BatchResult:
    """Run ``plan`` on each of ``files`` on a Dask cluster, writing into the folder ``out``
    (module docstring); returns a :class:`BatchResult`.

    ``workers``: the local cluster's worker processes (default :func:`default_workers`);
    ``scheduler``: the address of an existing Dask scheduler instead (``tcp://HOST:8786``);
    ``client``: an existing ``distributed.Client`` instead of either (kept open).
    ``progress``: called as ``progress(done, failed, running, total, eta_seconds, record)``
    after each file that ends (``record`` None for the first call, before any), ``eta_seconds``
    None until a file has ended. ``started``: called with the Dask dashboard's address (None
    for the local cluster, which is started without one to show) once the cluster is up.
    A KeyboardInterrupt ends the batch at once, leaving the
    records written so far (complete ones only) and no table; rerun to resume.
    """
    out = Path(out)
    records_dir, files_dir = out / "records", out / "files"
    files = [Path(f) for f in files]
    entries, records, pending = [], {}, []
    for path in files:
        name = record_name(path)
        try:
            sha = file_sha256(path)
        except OSError as exc:  # unreadable: its row says why, no worker needed
            records[name] = {"path": str(path), "sha256": None, "status": "failed",
                             "error": f"read: {exc.strerror or exc}"}
            entries.append((path, None, name))
            continue
        entries.append((path, sha, name))
        record = current_record(records_dir / f"{name}.json", sha, plan)
        if record is not None:
            records[name] = record
        else:
            pending.append((path, sha, name))
    skipped = sum(r.get("status") == "done" for r in records.values())
    total = len(files)
    failed = sum(r.get("status") != "done" for r in records.values())
    state = {"ended": 0, "failed": failed, "start": None, "workers": 1}
    dashboard = []

    def on_start(link, n_workers):
        dashboard.append(link)
        state["start"], state["workers"] = time.perf_counter(), n_workers
        if started is not None:
            started(link)
        if progress is not None:
            progress(skipped, failed, min(n_workers, len(pending)), total, None, None)

    def on_result(key, result):
        path, sha, name = key
        if isinstance(result, BaseException):  # a worker lost, say: the file's row says so
            result = {"path": str(path), "sha256": sha, "status": "failed",
                      "error": f"worker: {type(result).__name__}: {result}"}
        write_record(records_dir / f"{name}.json", result)  # a failed one is run again
        state["failed"] += result.get("status") != "done"
        records[name] = result
        state["ended"] += 1
        if progress is not None:  # the ETA: the rate so far (all workers together)
            left = len(pending) - state["ended"]
            eta = (time.perf_counter() - state["start"]) / state["ended"] * left
            progress(skipped + state["ended"], state["failed"],
                     min(state["workers"], left), total, eta, result)

    if pending:
        digest = plan.digest()[:8]
        cases = [((path, sha, name), (str(path), sha, plan, str(files_dir / name)),
                  f"roughgp-batch-{name}-{sha[:8]}-{digest}") for path, sha, name in pending]
        run_cases(_task, cases, workers=workers, scheduler=scheduler, client=client,
                  started=on_start, on_result=on_result)
    failed = state["failed"]
    dashboard = dashboard[0] if dashboard else None
    ordered = [records[name] for _, _, name in entries]
    tables = write_table(ordered, out)
    return BatchResult(records=ordered, ran=len(pending), skipped=skipped, failed=failed,
                       tables=tables, dashboard=dashboard)
