r"""Running the claims ledger, and its renderings as Markdown and JSON.

One :class:`~roughgp.ledger.types.Claim` per quantitative or checkable statement of Jawaid & Seewig: where it is
(section, equation, figure), the claim in a sentence, the paper's value where there is one,
the tolerance, the verdict this book reached, and a check (in the ``roughgp.ledger.checks_*`` modules)
that recomputes our value and tests the verdict's condition: for ``reproduced`` that our
value agrees with the paper's within the tolerance; for ``not reproducible as stated`` that
the disagreement is still there. :func:`run` runs the checks; an :class:`Outcome` whose
check no longer holds (or raised) has *regressed*: the verdict must be revisited, and
``roughgp reproduce`` exits non-zero.

Every check is quick by default (seconds to a minute) and uses the paper's sizes with
``full=True``. The book's chapter "Claims ledger" renders the same table, a regressed claim in
red (:func:`regression_notice`, ``red_regressions``).

Two environment variables steer :func:`run` for the tests of that reporting:
``ROUGHGP_LEDGER_ONLY=KEY[,KEY]`` runs only those claims (the book's chapter on one quick claim),
and ``ROUGHGP_LEDGER_FAULT=KEY[,KEY]`` reports those claims as regressed whatever their check
gives: a fault injection, marked in the outcome's value (:data:`FAULT_MARK`), never a result.
"""

from __future__ import annotations

import json
import os
import time
from pathlib import Path
from typing import Callable, Iterable

from roughgp.common.atomic import atomic_output
from roughgp.ledger.table import CLAIM_TABLE
from roughgp.ledger.types import Check, Claim, Outcome

__all__ = ["CLAIMS", "FAULT_ENV", "FAULT_MARK", "ONLY_ENV", "claim", "claim_keys", "run",
           "regression_notice", "to_markdown", "to_markdown_details", "to_records", "write"]

ONLY_ENV = "ROUGHGP_LEDGER_ONLY"
"""``KEY[,KEY]``: :func:`run` runs only these claims (with ``only`` too: the claims in both)."""
FAULT_ENV = "ROUGHGP_LEDGER_FAULT"
"""``KEY[,KEY]``: :func:`run` reports these claims as regressed (a fault injection, to test the
reporting: the chapter's red notice, the failing test, ``roughgp reproduce``'s exit 1)."""
FAULT_MARK = f"[fault injected by {FAULT_ENV}: not a result]"
"""Appended to the value of a claim that :data:`FAULT_ENV` made regress."""


def _claims() -> tuple[Claim, ...]:
    return tuple(Claim(**entry) for entry in CLAIM_TABLE)


CLAIMS: tuple[Claim, ...] = _claims()


def claim_keys() -> list[str]:
    """The keys of :data:`CLAIMS`, in the ledger's order."""
    return [c.key for c in CLAIMS]


def claim(key: str) -> Claim:
    """The claim with ``key``; a clear error listing the keys otherwise."""
    for c in CLAIMS:
        if c.key == key:
            return c
    raise ValueError(f"unknown claim {key!r}; the claims are: {', '.join(claim_keys())}")


def _keys_in(variable: str) -> list[str] | None:
    """The claim keys the environment variable ``variable`` names (``KEY[,KEY]``), each checked
    (a clear error naming the variable otherwise); None when it is unset or empty."""
    text = os.environ.get(variable, "").strip()
    if not text:
        return None
    keys = list(dict.fromkeys(k.strip() for k in text.split(",") if k.strip()))
    for key in keys:
        try:
            claim(key)
        except ValueError as exc:
            raise ValueError(f"{variable}={text}: {exc}") from None
    return keys


def run(*, full: bool | None = None, only: Iterable[str] | None = None,
        figures_dir: str | Path | None = None,
        progress: Callable[[str], None] | None = None) -> list[Outcome]:
    """Run the checks of the ledger (all, or the keys in ``only``), in the ledger's order.

    Args:
        full: the paper's sizes (slower) instead of the quick defaults; None: as
            ``ROUGHGP_FULL`` says (:func:`roughgp.common.settings.resolve_full`, the one rule).
        only: claim keys to run (each must exist); None runs all.
        figures_dir: where to save each check's figure as ``KEY.png`` (created with the first
            figure); None closes the figures unsaved.
        progress: called with a line of text before and after each check (e.g. ``print``),
            which starts with the claim's place in the run (``[3/25]``).

    Returns:
        the :class:`Outcome` of each claim run. A check that raises becomes an outcome
        with ``error`` set, so one broken check does not hide the others.

    Environment variables (for the tests of the reporting; unset in a real run):

    * ``ROUGHGP_LEDGER_ONLY=KEY[,KEY]`` (:data:`ONLY_ENV`): run only these claims; with
      ``only`` as well, the claims in both.
    * ``ROUGHGP_LEDGER_FAULT=KEY[,KEY]`` (:data:`FAULT_ENV`): report these claims as regressed
      whatever their check gives: a fault injection, to see that a regression reaches the
      book's page, the tests and ``roughgp reproduce``'s exit code. The check still runs; its
      outcome does not hold and its value ends with :data:`FAULT_MARK`, so nobody mistakes it
      for a result.

    A key that is no claim (or, for the fault, a claim without a check) is a ``ValueError``
    that names the variable.
    """
    import matplotlib
    import matplotlib.pyplot as plt
    from roughgp.common.shown_figures import save_for_page

    from roughgp.common.settings import resolve_full
    full = resolve_full(full)
    selected = CLAIMS if only is None else tuple(claim(k) for k in dict.fromkeys(only))
    narrowed, faults = _keys_in(ONLY_ENV), set(_keys_in(FAULT_ENV) or ())
    for key in faults:
        if claim(key).check is None:
            raise ValueError(f"{FAULT_ENV}: claim {key!r} is not checkable: it has no check "
                             f"that could fail")
    if narrowed is not None:
        selected = tuple(c for c in selected if c.key in narrowed)
    if figures_dir is not None:  # made with its first figure: an interrupt leaves no empty one
        figures_dir = Path(figures_dir)
    outcomes = []
    for i, c in enumerate(selected, start=1):
        if c.check is None:
            outcomes.append(Outcome(c, "-", True, 0.0))
            continue
        if progress:
            progress(f"[{i}/{len(selected)}] {c.key}: {c.where} ...")
        start = time.perf_counter()
        backend = matplotlib.get_backend()
        try:
            result = c.check(full)
            error = None
        except Exception as exc:  # noqa: BLE001 - reported in the ledger, not swallowed
            result, error = Check("-", False), f"{type(exc).__name__}: {exc}"
        seconds = time.perf_counter() - start
        path = None
        if result.figure is not None:
            if figures_dir is not None:
                path = str(figures_dir / f"{c.key}.png")
                with atomic_output(path) as partial:  # whole or not at all; the folder made
                    save_for_page(result.figure, partial, dpi=110)
            plt.close(result.figure)
        if matplotlib.get_backend() != backend:  # pragma: no cover - checks never switch
            matplotlib.use(backend)
        outcome = Outcome(c, result.value, bool(result.holds), seconds, path, error)
        if c.key in faults:
            outcome = Outcome(c, f"{result.value} {FAULT_MARK}", False, seconds, path, error)
        outcomes.append(outcome)
        if progress:
            progress(f"[{i}/{len(selected)}] {c.key}: {outcome.status} ({seconds:.1f} s) "
                     f"{outcome.value}")
    return outcomes


def to_records(outcomes: Iterable[Outcome]) -> list[dict]:
    """The outcomes as JSON-ready dicts (one per claim)."""
    out = []
    for o in outcomes:
        c = o.claim
        out.append({"key": c.key, "where": c.where, "claim": c.statement,
                    "paper_value": c.paper_value, "our_value": o.value,
                    "tolerance": c.tolerance, "verdict": c.verdict, "why": c.why,
                    "chapter": c.chapter, "status": o.status, "seconds": round(o.seconds, 2),
                    "figure": o.figure, "error": o.error})
    return out


def _cell(text: str) -> str:
    return str(text).replace("|", "\\|").replace("\n", " ")


def _where(c: Claim, chapter_links: bool) -> str:
    if not (chapter_links and c.chapter):
        return c.where
    page = c.chapter if "." in c.chapter else f"{c.chapter}.ipynb"
    return f"[{c.where}]({page})"


def _status(o: Outcome, red: bool) -> str:
    """``o.status``; for a regressed outcome with ``red``, as MyST's red badge (sphinx-design's
    role ``bdg-danger``, which the book loads)."""
    return f"{{bdg-danger}}`{o.status}`" if red and o.regressed else o.status


def regression_notice(outcomes: Iterable[Outcome]) -> str:
    """A red MyST admonition (class ``error``) that lists each regressed outcome with its value
    and error, for the top of the book's page; ``""`` when nothing regressed."""
    regressed = [o for o in outcomes if o.regressed]
    if not regressed:
        return ""
    n = len(regressed)
    lines = [":::{admonition} " + (f"{n} claims regressed" if n > 1 else "A claim regressed")
             + ": the verdict must be revisited", ":class: error", "",
             f"This build's check no longer gives the ledger's verdict for "
             f"{'these claims' if n > 1 else 'this claim'}: its status below is "
             f"{{bdg-danger}}`REGRESSED` ({{bdg-danger}}`ERROR` when the check raised). "
             f"`roughgp reproduce` exits 1 on it, and the tests fail.", ""]
    for o in regressed:
        said = f"ours: {' '.join(str(o.value).split())}"
        if o.error:
            said += f"; error: {' '.join(o.error.split())}"
        lines.append(f"* **{o.claim.where}** (`{o.claim.key}`, {o.claim.verdict}): {said}")
    return "\n".join(lines + [":::"]) + "\n"


def to_markdown(outcomes: Iterable[Outcome], *, chapter_links: bool = False,
                summary: bool = False, red_regressions: bool = False) -> str:
    """The ledger as a Markdown table: where, claim, paper, ours, tolerance, verdict (with
    its reason), status. ``summary``: only where, claim, verdict and status (narrow enough
    for a page; :func:`to_markdown_details` gives the rest). ``chapter_links``: link each
    claim's place to its chapter (``CHAPTER.ipynb``, for the book). ``red_regressions``: a
    regressed status as a red badge (MyST, for the book)."""
    if summary:
        lines = ["| where | claim | verdict | status |", "|---|---|---|---|"]
    else:
        lines = ["| where | claim | paper | ours | tolerance | verdict | status |",
                 "|---|---|---|---|---|---|---|"]
    for o in outcomes:
        c = o.claim
        status = _status(o, red_regressions) + ("" if o.error is None else f": {o.error}")
        if summary:
            cells = (_where(c, chapter_links), c.statement, f"**{c.verdict}**", status)
        else:
            verdict = f"**{c.verdict}**" + (f": {c.why}" if c.why else "")
            cells = (_where(c, chapter_links), c.statement, c.paper_value or "-", o.value,
                     c.tolerance or "-", verdict, status)
        lines.append("| " + " | ".join(_cell(x) for x in cells) + " |")
    return "\n".join(lines) + "\n"


def to_markdown_details(outcomes: Iterable[Outcome], *, chapter_links: bool = False,
                        red_regressions: bool = False) -> str:
    """One Markdown paragraph per claim: its place, the claim, the paper's value, ours,
    the tolerance, the verdict and why, and the time its check took (``chapter_links`` and
    ``red_regressions`` as for :func:`to_markdown`)."""
    blocks = []
    for o in outcomes:
        c = o.claim
        parts = [f"**{_where(c, chapter_links)}** (`{c.key}`): {c.statement}",
                 f"paper: {c.paper_value or '-'}; ours: {o.value}; tolerance: "
                 f"{c.tolerance or '-'}",
                 f"verdict: **{c.verdict}**" + (f", {c.why}" if c.why else "")
                 + f" ({_status(o, red_regressions)}, {o.seconds:.1f} s)"]
        if o.error:
            parts.append(f"error: {o.error}")
        blocks.append("\\\n".join(parts))
    return "\n\n".join(blocks) + "\n"


def write(outcomes: list[Outcome], out_dir: str | Path) -> tuple[Path, Path]:
    """Write ``ledger.md`` and ``ledger.json`` into ``out_dir`` (created); returns both
    paths."""
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    md, js = out_dir / "ledger.md", out_dir / "ledger.json"
    md.write_text("# roughgp claims ledger\n\n" + to_markdown(outcomes), encoding="utf-8")
    js.write_text(json.dumps(to_records(outcomes), indent=1), encoding="utf-8")
    return md, js
