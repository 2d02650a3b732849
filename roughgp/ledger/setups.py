"""The claims whose value comes from an optimiser or a random search, run under several
numerical set-ups: a verdict must not depend on the machine.

A claim marked ``search`` in the ledger (:attr:`~roughgp.ledger.types.Claim.search`: a
multi-start fit, a Markov chain) reaches its value along a path that the last bits of the
arithmetic can change: another CPU, BLAS kernel or thread count. Its verdict is a reproduction
only if it holds whichever path is taken. :func:`run_setups` runs those claims once per
:class:`Setup` of :data:`SETUPS` (1 and 2 BLAS threads; optimiser and chain starts as computed,
and moved by 1e-6, :mod:`roughgp.common.numerics`), each in a fresh Python
process (the set-up's environment, no results cache, no result shared between set-ups), and
:func:`differences` lists the claims whose verdict is not the same under all of them.
``roughgp reproduce --setups`` runs it and exits 1 on any difference; CI runs it on every
submission.

The set-ups run side by side (``jobs`` processes at a time): each is a separate process with
its own environment, which is what a set-up is, so no work is split by hand.
"""

from __future__ import annotations

import dataclasses
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Callable, Iterable

from roughgp.common import numerics
from roughgp.common.results_cache import ENV as RESULTS_CACHE_ENV
from roughgp.common.settings import pick
from roughgp.ledger.runner import CLAIMS, claim, run, to_records
from roughgp.ledger.types import Outcome

__all__ = ["Setup", "SETUPS", "SetupRun", "search_keys", "run_setups", "differences",
           "to_markdown", "main"]

THREAD_VARIABLES = ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS")


@dataclasses.dataclass(frozen=True)
class Setup:
    """A numerical set-up: the BLAS libraries' thread count (``blas_threads``, 1 or more) and
    the seed of the start perturbation (``start_jitter``: 0 for the starts as computed)."""

    blas_threads: int
    start_jitter: int

    def __post_init__(self):
        if not (isinstance(self.blas_threads, int) and self.blas_threads >= 1):
            raise ValueError(f"blas_threads must be an integer >= 1, got {self.blas_threads!r}")
        if not (isinstance(self.start_jitter, int) and 0 <= self.start_jitter < 2**32):
            raise ValueError(f"start_jitter must be an integer in [0, 2**32), got "
                             f"{self.start_jitter!r}")

    @property
    def label(self) -> str:
        starts = ("starts as computed" if self.start_jitter == 0
                  else f"starts jittered (seed {self.start_jitter})")
        return f"{self.blas_threads} BLAS thread{'s' if self.blas_threads > 1 else ''}, {starts}"

    def environment(self, base: dict | None = None) -> dict:
        """``base`` (default: this process's environment) with this set-up's thread variables
        and jitter seed, and without the results cache (every set-up computes)."""
        env = dict(os.environ if base is None else base)
        for name in THREAD_VARIABLES:
            env[name] = str(self.blas_threads)
        env[numerics.ENV] = str(self.start_jitter)
        env.pop(RESULTS_CACHE_ENV, None)
        return env

    @classmethod
    def of_this_process(cls) -> "Setup":
        """The set-up this process runs under (:func:`roughgp.common.numerics.setup`)."""
        now = numerics.setup()
        return cls(int(now["blas_threads"]), int(now["start_jitter"]))


SETUPS = (Setup(1, 0), Setup(2, 1))
"""The set-ups CI compares: the book's own run (the tests run each notebook on one BLAS thread,
starts as computed) and two threads with jittered starts: both the thread count and the starts
differ. More set-ups find more (pass them to :func:`run_setups`); each costs the search claims'
time again (about 2 to 3 minutes at the quick sizes on the 2-core machine)."""


@dataclasses.dataclass
class SetupRun:
    """The outcomes of the claims under one set-up (``reused``: taken from a saved run)."""

    setup: Setup
    outcomes: list[Outcome]
    seconds: float
    reused: bool = False


def search_keys() -> list[str]:
    """The keys of the claims marked ``search``, in the ledger's order."""
    return [c.key for c in CLAIMS if c.search]


def _child_command(keys, full, out):
    return [sys.executable, "-m", "roughgp.ledger.setups", "--out", str(out),
            pick("--quick", "--full", full=full), *keys]


def _outcomes_from(records) -> list[Outcome]:
    return [Outcome(claim(r["key"]), r["our_value"], r["status"] in ("ok", "not run"),
                    float(r["seconds"]), None, r.get("error")) for r in records]


def run_setups(keys: Iterable[str] | None = None, setups: Iterable[Setup] = SETUPS, *,
               full: bool = False, reuse: dict | None = None, jobs: int = 2,
               progress: Callable[[str], None] | None = None,
               child: Callable | None = None) -> list[SetupRun]:
    """Run the claims ``keys`` (default: :func:`search_keys`) under each set-up, each in its own
    process, ``jobs`` at a time.

    Args:
        keys: claim keys (each must exist).
        setups: the :class:`Setup` s to compare (at least two).
        full: the paper's sizes.
        reuse: ``{Setup: [Outcome, ...]}`` already run under that set-up (the book's saved run);
            those set-ups are not run again.
        jobs: processes at a time (>= 1).
        progress: called with a line of text as each set-up starts and ends.
        child: ``child(keys, full, out) -> argv`` of the process that runs the claims and writes
            their records to ``out`` (default: this module's :func:`main`; the tests pass a
            deliberately fragile one).

    Returns:
        a :class:`SetupRun` per set-up, in the order given.
    """
    keys = search_keys() if keys is None else [claim(k).key for k in keys]
    setups = list(setups)
    if len(setups) < 2:
        raise ValueError(f"setups must hold at least two set-ups to compare, got {len(setups)}")
    if not (isinstance(jobs, int) and jobs >= 1):
        raise ValueError(f"jobs must be an integer >= 1, got {jobs!r}")
    say = progress or (lambda text: None)
    results: dict[Setup, SetupRun] = {}
    for setup, outcomes in (reuse or {}).items():
        kept = [o for o in outcomes if o.claim.key in keys]
        if setup in setups and len(kept) == len(keys):
            results[setup] = SetupRun(setup, kept, sum(o.seconds for o in kept), reused=True)
            say(f"set-up '{setup.label}': reusing the saved run")
    waiting = [s for s in setups if s not in results]
    with tempfile.TemporaryDirectory() as folder:
        running = []
        while waiting or running:
            while waiting and len(running) < jobs:
                setup = waiting.pop(0)
                out = Path(folder) / f"setup-{setups.index(setup)}.json"
                log = out.with_suffix(".log")
                say(f"set-up '{setup.label}': running {len(keys)} claim(s) ...")
                with log.open("w", encoding="utf-8") as sink:  # a file: no pipe to fill up
                    process = subprocess.Popen((child or _child_command)(keys, full, out),
                                               env=setup.environment(), stdout=sink,
                                               stderr=subprocess.STDOUT)
                running.append((setup, process, out, log, time.perf_counter()))
            setup, process, out, log, start = running.pop(0)
            process.wait()
            seconds = time.perf_counter() - start
            if process.returncode != 0 or not out.is_file():
                text = log.read_text(encoding="utf-8", errors="replace")
                raise RuntimeError(f"the claims under set-up '{setup.label}' did not run "
                                   f"(exit {process.returncode}): {text[-2000:]}")
            records = json.loads(out.read_text(encoding="utf-8"))
            results[setup] = SetupRun(setup, _outcomes_from(records["claims"]), seconds)
            say(f"set-up '{setup.label}': done in {seconds:.0f} s")
    return [results[s] for s in setups]


def differences(runs: list[SetupRun]) -> list[str]:
    """The claims whose verdict (holds or not, or an error) is not the same under every
    set-up: one line per claim naming the set-ups on each side; empty when all agree."""
    lines = []
    keys = [o.claim.key for o in runs[0].outcomes]
    for key in keys:
        status = {r.setup: next(o.status for o in r.outcomes if o.claim.key == key)
                  for r in runs}
        if len(set(status.values())) > 1:
            parts = "; ".join(f"{s.label}: {v}" for s, v in status.items())
            lines.append(f"{key}: {parts}")
    return lines


def to_markdown(runs: list[SetupRun]) -> str:
    """The claims against the set-ups as a Markdown table (status and our value per set-up)."""
    lines = ["| claim | " + " | ".join(r.setup.label for r in runs) + " |",
             "|---|" + "---|" * len(runs)]
    for i, outcome in enumerate(runs[0].outcomes):
        cells = [f"{r.outcomes[i].status}: {r.outcomes[i].value}".replace("|", "\\|")
                 for r in runs]
        lines.append(f"| {outcome.claim.key} | " + " | ".join(cells) + " |")
    return "\n".join(lines) + "\n"


def main(argv=None) -> int:
    """The child process of :func:`run_setups`: run the claims named on the command line under
    this process's set-up and write their records and the set-up as JSON (``--out FILE``)."""
    import argparse

    parser = argparse.ArgumentParser(prog="python -m roughgp.ledger.setups",
                                     description=main.__doc__.splitlines()[0])
    parser.add_argument("keys", nargs="+")
    parser.add_argument("--out", required=True)
    size = parser.add_mutually_exclusive_group(required=True)
    size.add_argument("--full", dest="full", action="store_true")
    size.add_argument("--quick", dest="full", action="store_false")
    args = parser.parse_args(argv)
    import matplotlib

    matplotlib.use("Agg")
    outcomes = run(full=args.full, only=args.keys)
    record = {"setup": numerics.setup(), "claims": to_records(outcomes)}
    Path(args.out).write_text(json.dumps(record, indent=1), encoding="utf-8")
    return 0


if __name__ == "__main__":  # pragma: no cover - the child process of run_setups
    sys.exit(main())
