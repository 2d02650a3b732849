"""The book's page as a figure meets it: the text column's width, the smallest text allowed, and
the size at which a figure's text appears once the figure is shown (and shrunk to the column).

:mod:`roughgp.common.plotting` holds the figures to it; :mod:`roughgp.common.shown_figures`
records it with each figure a chapter shows.
"""

from __future__ import annotations

__all__ = ["PAGE_WIDTH_PX", "MIN_FONT_PT", "points_on_page", "visible_texts",
           "smallest_text_on_page"]

PAGE_WIDTH_PX = 688
"""Width of the book's text column in CSS pixels (sphinx-book-theme 1.x in a 1280 px window,
measured on the built page: the article's content box): an image wider than this is shrunk to
it, so a wide figure's text is shrunk with it."""

MIN_FONT_PT = 9.0
"""The smallest text size on the page (CSS points) that the book's figures allow."""


def points_on_page(fig, page_width_px=PAGE_WIDTH_PX, shown_width_px=None, dpi=None) -> float:
    """CSS points on the page per point of ``fig``'s text, for the figure drawn at ``dpi``
    (by default ``fig.dpi``) and shown as an image ``shown_width_px`` pixels wide (by default
    its full size)."""
    dpi = fig.dpi if dpi is None else dpi
    if shown_width_px is None:
        shown_width_px = fig.get_figwidth() * dpi
    shrink = min(1.0, page_width_px / shown_width_px)
    return dpi / 72.0 * shrink * 0.75


def visible_texts(fig):
    """Every visible, non-empty text of ``fig`` (ticks, labels, titles, legends, colour bars,
    annotations), after a draw."""
    import matplotlib.text

    fig.canvas.draw()
    for text in fig.findobj(matplotlib.text.Text):
        if text.get_text().strip() and text.get_visible():
            yield text


def smallest_text_on_page(fig, shown_width_px, page_width_px=PAGE_WIDTH_PX, dpi=None):
    """The size (CSS points) of the smallest visible text of ``fig`` on the page, for the figure
    drawn at ``dpi`` (by default ``fig.dpi``, as a notebook shows it) into an image
    ``shown_width_px`` pixels wide (cropped to its drawn content); None when it has no text."""
    sizes = [text.get_fontsize() for text in visible_texts(fig)]
    if not sizes:
        return None
    return min(sizes) * points_on_page(fig, page_width_px, shown_width_px, dpi)
