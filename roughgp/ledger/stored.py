"""A run of the ledger kept on disk, so that the book's chapter and ``roughgp reproduce`` share it.

:func:`save` writes what :func:`~roughgp.ledger.runner.write` writes (``ledger.md``,
``ledger.json``) and ``run.json``: when the run was made, at which sizes, of which claims, and
the :func:`fingerprint` of what its results depend on. :func:`load` gives the outcomes back
only if that run is complete and its fingerprint is today's; otherwise it says why not, and the
caller runs the checks. The chapter "Claims ledger" saves its run in ``book/_build/ledger``;
``roughgp reproduce --out book/_build/ledger --reuse`` then reports that run instead of computing
every check a second time.
"""

from __future__ import annotations

import hashlib
import json
import platform
import time
from importlib.metadata import PackageNotFoundError, version
from pathlib import Path

from roughgp.common import numerics
from roughgp.common.digests import source_files, update_with_files
from roughgp.ledger.runner import CLAIMS, claim, write
from roughgp.ledger.types import Outcome

__all__ = ["RUN_FILE", "fingerprint", "load", "save", "saved_setup"]

RUN_FILE = "run.json"
_LIBRARIES = ("numpy", "scipy", "torch", "gpytorch", "emcee", "matplotlib", "SurfaceTopography")


def fingerprint(full: bool) -> str:
    """SHA-256 over what the checks' results depend on: roughgp's own files, the data files the
    measured-surface checks read, the versions of Python and of the numerical libraries, and
    the size setting ``full``."""
    h = hashlib.sha256()
    package = Path(__file__).resolve().parents[1]
    from roughgp.experiments.measured_surfaces import DATA

    update_with_files(h, source_files(package), package)
    update_with_files(h, source_files(DATA), DATA)
    for name in _LIBRARIES:
        try:
            h.update(f"{name} {version(name)}\0".encode())
        except PackageNotFoundError:
            h.update(f"{name} -\0".encode())
    h.update(f"python {platform.python_version()} full {bool(full)}".encode())
    return h.hexdigest()


def save(outcomes: list[Outcome], out_dir: str | Path, *, full: bool) -> Path:
    """Write ``ledger.md``, ``ledger.json`` and ``run.json`` into ``out_dir``; returns the
    path of ``run.json``."""
    out_dir = Path(out_dir)
    write(outcomes, out_dir)
    run = {"format": "roughgp-ledger-run", "version": 1,
           "created": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime()),
           "full": bool(full), "keys": [o.claim.key for o in outcomes],
           "fingerprint": fingerprint(full), "setup": numerics.setup()}
    path = out_dir / RUN_FILE
    path.write_text(json.dumps(run, indent=1), encoding="utf-8")
    return path


def load(out_dir: str | Path, *, full: bool) -> tuple[list[Outcome] | None, str]:
    """The outcomes of the complete run saved in ``out_dir`` at sizes ``full``, if nothing it
    depends on changed since: ``(outcomes, "the run of DATE")``; else ``(None, why not)``."""
    out_dir = Path(out_dir)
    try:
        run = json.loads((out_dir / RUN_FILE).read_text(encoding="utf-8"))
        records = json.loads((out_dir / "ledger.json").read_text(encoding="utf-8"))
    except FileNotFoundError:
        return None, f"no saved run in {out_dir}"
    except (OSError, ValueError) as exc:
        return None, f"the saved run in {out_dir} is unreadable ({exc})"
    if run.get("format") != "roughgp-ledger-run" or run.get("version") != 1:
        return None, f"{out_dir / RUN_FILE} is not a ledger run of this version"
    if bool(run.get("full")) != bool(full):
        return None, f"the saved run used {'the paper' if run.get('full') else 'quick'} sizes"
    if run.get("keys") != [c.key for c in CLAIMS] or [r.get("key") for r in records] != \
            run.get("keys"):
        return None, "the saved run does not hold every claim of today's ledger"
    if run.get("fingerprint") != fingerprint(full):
        return None, "roughgp, its data or a library changed since the saved run"
    outcomes = []
    for r in records:
        figure = r.get("figure")
        if figure and not Path(figure).is_file():
            return None, f"the saved run's figure {figure} is missing"
        outcomes.append(Outcome(claim(r["key"]), r["our_value"], r["status"] in ("ok", "not run"),
                                float(r["seconds"]), figure, r.get("error")))
    return outcomes, f"the run of {run.get('created', '?')}"


def saved_setup(out_dir: str | Path) -> dict | None:
    """The numerical set-up (:func:`roughgp.common.numerics.setup`) of the run saved in
    ``out_dir``, or None where the run or its record of the set-up is missing."""
    try:
        run = json.loads((Path(out_dir) / RUN_FILE).read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return None
    found = run.get("setup")
    return found if isinstance(found, dict) else None
