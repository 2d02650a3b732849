"""What an executed chapter shows fits the book's column: no figure whose text is unreadable on
the page (too small, or shrunk with a figure wider than the column), no printed line wider than
the page.

The book's text column is :data:`roughgp.common.page.PAGE_WIDTH_PX` CSS pixels wide
(688 px). A figure shown wider is shrunk to it, with its text; a printed output line longer than
:data:`MAX_LINE` characters (the column in the theme's monospace font) gets a scroll bar. (The
book drops what a cell writes to stderr: ``stderr_output: remove`` in ``book/_config.yml``.)

``conftest.py`` passes nbmake's result of every notebook through :func:`fail_on_overflow`, as it
does through :func:`booktools.findings.fail_on_findings`: a chapter or lab that shows such a
figure or line fails its test, naming the cell and what to change. The figures' text sizes come
from the kernel: :func:`roughgp.common.plotting.use_style` records, with each figure it shows,
its shown width and the size of its smallest text on the page
(:data:`roughgp.common.shown_figures.SHOWN_KEY`); a figure a chapter shows from a file carries
it in the file (:func:`roughgp.common.shown_figures.save_for_page`). A figure wider than the
column without that record fails too: its text cannot be measured (one as narrow as the column
is shown at its size).
"""

from __future__ import annotations

from booktools.findings import failed
from roughgp.common.page import MIN_FONT_PT, PAGE_WIDTH_PX
from roughgp.common.page_text import PAGE_COLUMNS
from roughgp.common.shown_figures import PNG_TEXT_KEY, SHOWN_KEY, png_text, png_width

MAX_LINE = PAGE_COLUMNS
"""Characters of a printed output line that fit the column (the theme's monospace code font at
688 px; pandas' and numpy's default 80-character wrap fits)."""

HIDDEN_OUTPUT_TAGS = {"remove-cell", "remove-output"}
"""Cell tags whose outputs the page does not show (their figures still count: a glued figure
is shown where it is pasted)."""

# outputs a page shows instead of the text/plain form
_RICHER = ("text/html", "text/markdown", "text/latex", "image/png", "image/svg+xml", "image/jpeg")

__all__ = ["MAX_LINE", "HIDDEN_OUTPUT_TAGS", "fail_on_overflow", "overflow"]


def _text(value) -> str:
    return "".join(value) if isinstance(value, list) else (value or "")


def _long_lines(text: str) -> list[str]:
    return [line for line in text.splitlines() if len(line.rstrip()) > MAX_LINE]


def _smallest_text(output, png):
    """The recorded size of a shown figure's smallest text on the page: from the kernel's record
    in the output's metadata, or from the PNG itself (a figure saved by
    :func:`~roughgp.common.shown_figures.save_for_page`); ``(False, None)`` when neither
    recorded it, ``(True, None)`` when the figure has no text."""
    shown = output.get("metadata", {}).get("image/png", {})
    if SHOWN_KEY in shown:
        return True, shown[SHOWN_KEY].get("smallest_text_pt")
    text = png_text(png).get(PNG_TEXT_KEY)
    return (True, float(text)) if text is not None else (False, None)


def _figure_problem(output, where: str) -> str | None:
    png = output.get("data", {}).get("image/png")
    if png is None:
        return None
    width = png_width(png)
    recorded, smallest = _smallest_text(output, png)
    if not recorded:
        if width <= PAGE_WIDTH_PX:
            return None  # not shrunk; drawn without the book's style (a lab's own figure)
        return (f"{where}: a figure {width} px wide is shrunk to the {PAGE_WIDTH_PX} px column "
                "and its text cannot be measured (draw it after "
                "roughgp.common.plotting.use_style(), or save it with save_for_page)")
    if smallest is None or smallest >= MIN_FONT_PT:
        return None
    shrunk = (f"{width} px wide, shrunk to the {PAGE_WIDTH_PX} px column"
              if width > PAGE_WIDTH_PX else f"{width} px wide")
    return (f"{where}: a figure {shrunk}, with text of {smallest:.1f} pt on the page (at least "
            f"{MIN_FONT_PT:g} pt): make it narrower or its smallest text larger")


def overflow(nb) -> list[str]:
    """What the executed notebook ``nb`` shows that does not fit the column: each figure with
    text under :data:`~roughgp.common.page.MIN_FONT_PT` on the page (shrunk to the column
    when wider than :data:`~roughgp.common.page.PAGE_WIDTH_PX`; a wider figure that was not
    measured fails too), and each shown
    output line over :data:`MAX_LINE` characters; one line each, naming the code cell (counted
    from 1, as nbmake does). Empty when everything fits."""
    problems = []
    code_cells = [cell for cell in nb.cells if cell.cell_type == "code"]
    for number, cell in enumerate(code_cells, start=1):
        shows_text = not HIDDEN_OUTPUT_TAGS & set(cell.get("metadata", {}).get("tags", []))
        where = f"code cell {number}"
        for output in cell.get("outputs", []):
            figure = _figure_problem(output, where)
            if figure:
                problems.append(figure)
            if not shows_text:
                continue
            if output.get("output_type") == "stream":
                if output.get("name") == "stderr":  # dropped by the book (stderr_output)
                    continue
                text = _text(output.get("text"))
            elif output.get("output_type") in ("execute_result", "display_data"):
                data = output.get("data", {})
                if any(kind in data for kind in _RICHER):
                    continue
                text = _text(data.get("text/plain"))
            else:
                continue
            for line in _long_lines(text):
                problems.append(f"{where}: an output line of {len(line.rstrip())} characters "
                                f"(the column holds {MAX_LINE}): {line[:60].rstrip()}...")
    return problems


def fail_on_overflow(result, path=None):
    """nbmake's ``NotebookResult`` ``result``, failed (its ``error`` set, listing each problem)
    when the notebook ran without error but shows what does not fit the column
    (:func:`overflow`); otherwise unchanged."""
    if result is None or result.error is not None:
        return result
    problems = overflow(result.nb)
    if not problems:
        return result
    where = f"{path}: " if path is not None else ""
    summary = f"{where}{len(problems)} output(s) wider than the book's column"
    trace = (f"{where}what the page shows must fit its {PAGE_WIDTH_PX} px column "
             "(booktools/page_fit.py):\n" + "\n".join(f"  {p}" for p in problems))
    return failed(result, summary, trace)
