"""A regressed claim: shown by the book, failed by the tests.

The chapter "Claims ledger" (``book/claims.ipynb``) runs every check of the ledger. A claim whose
check no longer gives its verdict is a finding the reader must see, so the chapter does not stop
the book build: it shows the claim in red (a notice at the top of the page, the status in the
table) and every page is written. The tests must still fail on it, as ``roughgp reproduce``
does (exit 1). So the chapter also glues the list of its regressed claims, hidden, in a cell
tagged ``remove-input``::

    glue("regressed_claims", ["eq5-duality: <value or error>", ...], display=False)

and ``conftest.py`` passes nbmake's result of every notebook through :func:`fail_on_findings`:
the notebook nbmake ran, or the run taken from the notebook cache with its stored outputs
(:func:`booktools.notebook_cache.execute`), so a run with a regression stored in the cache (it
passed nbmake: no cell raised) fails the test again on every ``make test`` until the claim
holds, and ``make book`` renders that same run with the regression on the page.
"""

from __future__ import annotations

import ast
import dataclasses

REGRESSED = "regressed_claims"
# what myst_nb.glue(..., display=False) writes: the display data under this prefix, and the
# glue's name in the output's metadata
GLUE_PREFIX = "application/papermill.record/"

__all__ = ["REGRESSED", "fail_on_findings", "failed", "glued", "regressed_claims"]


def glued(nb, name: str):
    """The value glued as ``name`` (``myst_nb.glue(name, value, display=False)``, or shown) in
    the executed notebook ``nb``, from its ``text/plain`` repr (a Python literal); None when the
    notebook glued no ``name`` (not executed, or not this notebook). The last one wins."""
    found = None
    for cell in nb.cells:
        for output in cell.get("outputs", []) if cell.cell_type == "code" else []:
            if output.get("metadata", {}).get("scrapbook", {}).get("name") != name:
                continue
            data = output.get("data", {})
            text = data.get(GLUE_PREFIX + "text/plain", data.get("text/plain"))
            if text is None:
                continue
            text = "".join(text) if isinstance(text, list) else text
            try:
                found = ast.literal_eval(text)
            except (ValueError, SyntaxError):
                found = text
    return found


def regressed_claims(nb) -> list[str]:
    """The regressed claims the executed notebook ``nb`` glued as :data:`REGRESSED` (each
    ``"KEY: value or error"``); empty when it glued none."""
    value = glued(nb, REGRESSED)
    if value is None:
        return []
    return [str(v) for v in value] if isinstance(value, (list, tuple)) else [str(value)]


def fail_on_findings(result, path=None):
    """nbmake's ``NotebookResult`` ``result``, failed (its ``error`` set, naming each claim)
    when the notebook ran without error but glued regressed claims; otherwise unchanged."""
    if result is None or result.error is not None:
        return result
    claims = regressed_claims(result.nb)
    if not claims:
        return result
    where = f"{path}: " if path is not None else ""
    summary = (f"{where}{len(claims)} regressed claim(s): "
               + ", ".join(c.split(":")[0] for c in claims))
    trace = (f"{where}the claims ledger ran, and these checks no longer give their verdict "
             f"(the book shows them in red; the verdict must be revisited):\n"
             + "\n".join(f"  {c}" for c in claims)
             + f"\n(the list the notebook glued as {REGRESSED!r}; see roughgp reproduce)")
    index = next((i for i, cell in enumerate(result.nb.cells) if cell.cell_type == "code"
                  and any(o.get("metadata", {}).get("scrapbook", {}).get("name") == REGRESSED
                          for o in cell.get("outputs", []))), -1)
    return failed(result, summary, trace, index)


def failed(result, summary: str, trace: str, index: int = -1):
    """nbmake's ``NotebookResult`` ``result`` with its ``error`` set to ``summary`` and
    ``trace`` at cell ``index`` (-1: no one cell): how a notebook that ran without error fails
    its test on what it reports (here, and :mod:`booktools.page_fit`)."""
    from nbmake.nb_result import NotebookError

    return dataclasses.replace(result, error=NotebookError(summary, trace, index))
