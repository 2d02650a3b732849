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
``full=True``. The book's chapter "Claims ledger" renders the same table.
"""

from __future__ import annotations

import json
import time
from pathlib import Path
from typing import Callable, Iterable

from roughgp.ledger.table import CLAIM_TABLE
from roughgp.ledger.types import Check, Claim, Outcome

__all__ = ["CLAIMS", "claim", "claim_keys", "run",
           "to_markdown", "to_markdown_details", "to_records", "write"]


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


def run(*, full: bool | None = None, only: Iterable[str] | None = None,
        figures_dir: str | Path | None = None,
        progress: Callable[[str], None] | None = None) -> list[Outcome]:
    """Run the checks of the ledger (all, or the keys in ``only``), in the ledger's order.

    Args:
        full: the paper's sizes (slower) instead of the quick defaults; None: as
            ``ROUGHGP_FULL`` says (:func:`roughgp.common.settings.resolve_full`, the one rule).
        only: claim keys to run (each must exist); None runs all.
        figures_dir: where to save each check's figure as ``KEY.png`` (created); None
            closes the figures unsaved.
        progress: called with a line of text before and after each check (e.g. ``print``),
            which starts with the claim's place in the run (``[3/25]``).

    Returns:
        the :class:`Outcome` of each claim run. A check that raises becomes an outcome
        with ``error`` set, so one broken check does not hide the others.
    """
    import matplotlib
    import matplotlib.pyplot as plt

    from roughgp.common.settings import resolve_full
    full = resolve_full(full)
    selected = CLAIMS if only is None else tuple(claim(k) for k in dict.fromkeys(only))
    if figures_dir is not None:
        figures_dir = Path(figures_dir)
        figures_dir.mkdir(parents=True, exist_ok=True)
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
                result.figure.savefig(path, dpi=110, bbox_inches="tight")
            plt.close(result.figure)
        if matplotlib.get_backend() != backend:  # pragma: no cover - checks never switch
            matplotlib.use(backend)
        outcome = Outcome(c, result.value, bool(result.holds), seconds, path, error)
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


def to_markdown(outcomes: Iterable[Outcome], *, chapter_links: bool = False,
                summary: bool = False) -> str:
    """The ledger as a Markdown table: where, claim, paper, ours, tolerance, verdict (with
    its reason), status. ``summary``: only where, claim, verdict and status (narrow enough
    for a page; :func:`to_markdown_details` gives the rest). ``chapter_links``: link each
    claim's place to its chapter (``CHAPTER.ipynb``, for the book)."""
    if summary:
        lines = ["| where | claim | verdict | status |", "|---|---|---|---|"]
    else:
        lines = ["| where | claim | paper | ours | tolerance | verdict | status |",
                 "|---|---|---|---|---|---|---|"]
    for o in outcomes:
        c = o.claim
        status = o.status if o.error is None else f"ERROR: {o.error}"
        if summary:
            cells = (_where(c, chapter_links), c.statement, f"**{c.verdict}**", status)
        else:
            verdict = f"**{c.verdict}**" + (f": {c.why}" if c.why else "")
            cells = (_where(c, chapter_links), c.statement, c.paper_value or "-", o.value,
                     c.tolerance or "-", verdict, status)
        lines.append("| " + " | ".join(_cell(x) for x in cells) + " |")
    return "\n".join(lines) + "\n"


def to_markdown_details(outcomes: Iterable[Outcome], *, chapter_links: bool = False) -> str:
    """One Markdown paragraph per claim: its place, the claim, the paper's value, ours,
    the tolerance, the verdict and why, and the time its check took."""
    blocks = []
    for o in outcomes:
        c = o.claim
        parts = [f"**{_where(c, chapter_links)}** (`{c.key}`): {c.statement}",
                 f"paper: {c.paper_value or '-'}; ours: {o.value}; tolerance: "
                 f"{c.tolerance or '-'}",
                 f"verdict: **{c.verdict}**" + (f", {c.why}" if c.why else "")
                 + f" ({o.status}, {o.seconds:.1f} s)"]
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
