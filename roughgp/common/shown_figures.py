"""Figures as the book's page shows them: their width and the size of their smallest text.

A figure shrunk to the book's column (:data:`roughgp.common.page.PAGE_WIDTH_PX`) shrinks its
text with it. The tests hold every executed chapter to :data:`roughgp.common.page.MIN_FONT_PT`
on the page (``booktools.page_fit``); to do so they need each shown figure's text sizes, which
the image alone does not tell. This module records them where the figure goes:

* in a notebook, :func:`record_shown_figures` (called by
  :func:`roughgp.common.plotting.use_style`) adds to each inline figure's output metadata its
  shown width and smallest text on the page (:data:`SHOWN_KEY`);
* a figure a chapter shows from a file is saved by :func:`save_for_page`, which writes the size
  into the PNG itself (:data:`PNG_TEXT_KEY`, read back by :func:`png_text`).
"""

from __future__ import annotations

import base64
import io

import matplotlib.pyplot as plt

from roughgp.common.page import smallest_text_on_page

__all__ = ["SHOWN_KEY", "PNG_TEXT_KEY", "png_width", "png_text", "save_for_page",
           "record_shown_figures"]


SHOWN_KEY = "roughgp"
"""Key of the record :func:`use_style` adds to the metadata of each figure a notebook shows:
``{"width_px": w, "smallest_text_pt": s}`` (``booktools.page_fit`` reads it)."""


PNG_TEXT_KEY = "roughgp smallest text pt"
"""Keyword of the PNG text chunk in which :func:`save_for_page` writes the size of the figure's
smallest text on the page (CSS points), for an image that a chapter shows from a file."""


def _png_bytes(data) -> bytes:
    return base64.b64decode(data) if isinstance(data, str) else bytes(data)


def png_width(data) -> int:
    """Pixel width of a PNG given as bytes or base64 text (from its IHDR chunk)."""
    head = base64.b64decode(data[:64]) if isinstance(data, str) else bytes(data[:24])
    return int.from_bytes(head[16:20], "big")


def png_text(data) -> dict[str, str]:
    """The text chunks (``tEXt``) of a PNG given as bytes or base64 text: keyword -> text."""
    raw, found, at = _png_bytes(data), {}, 8
    while at + 8 <= len(raw):
        length, kind = int.from_bytes(raw[at:at + 4], "big"), raw[at + 4:at + 8]
        if kind == b"tEXt":
            keyword, _, text = raw[at + 8:at + 8 + length].partition(b"\0")
            found[keyword.decode("latin-1")] = text.decode("latin-1")
        if kind == b"IEND":
            break
        at += 12 + length
    return found


def save_for_page(fig, path, dpi=110) -> float | None:
    """Save ``fig`` as a PNG at ``dpi`` (cropped to its content) for a chapter to show from
    the file, with the size of its smallest text on the page written in the file
    (:data:`PNG_TEXT_KEY`, read by ``booktools.page_fit``); returns that size (CSS points)."""
    draft = io.BytesIO()
    fig.savefig(draft, format="png", dpi=dpi, bbox_inches="tight")
    smallest = smallest_text_on_page(fig, png_width(draft.getvalue()), dpi=dpi)
    metadata = {} if smallest is None else {PNG_TEXT_KEY: f"{smallest:.2f}"}
    fig.savefig(path, format="png", dpi=dpi, bbox_inches="tight", metadata=metadata)
    return smallest


def record_shown_figures():
    """In an IPython kernel: every figure shown inline carries in its output's metadata its
    shown width and the smallest size of its text on the page (:data:`SHOWN_KEY`), so the tests
    can hold each executed chapter to the column (``booktools.page_fit``). Outside IPython,
    nothing."""
    try:
        from IPython import get_ipython
    except ImportError:
        return
    shell = get_ipython()
    if shell is None or not hasattr(shell, "display_formatter"):
        return
    import matplotlib
    from matplotlib.figure import Figure

    if "inline" not in matplotlib.get_backend():
        return
    plt.switch_backend(matplotlib.get_backend())  # the inline backend registers its formatter
    formatter = shell.display_formatter.formatters["image/png"]
    printer = formatter.type_printers.get(Figure)
    if printer is None or getattr(printer, "records_page_size", False):
        return

    def shown(fig):
        data = printer(fig)
        if data is None:
            return None
        width = png_width(data)
        return data, {SHOWN_KEY: {"width_px": width,
                                  "smallest_text_pt": smallest_text_on_page(fig, width)}}

    shown.records_page_size = True
    formatter.for_type(Figure, shown)
