"""Text that a chapter prints, fitted to the book's column.

The book's text column (:data:`roughgp.common.plotting.PAGE_WIDTH_PX`, 688 px) holds
:data:`PAGE_COLUMNS` characters of the theme's monospace font; a longer output line gets a scroll
bar (``booktools.page_fit`` fails a chapter that prints one). :func:`say` prints a sentence or a
report wrapped to that width; a table is better shown as a pandas DataFrame (HTML, wrapped by the
page).
"""

from __future__ import annotations

import textwrap

PAGE_COLUMNS = 81
"""Characters of a printed line that fit the book's column."""

__all__ = ["PAGE_COLUMNS", "fit_to_page", "say"]


def fit_to_page(text, width: int = PAGE_COLUMNS) -> str:
    """``text`` (any object, as ``str``) with each of its lines wrapped to ``width``
    characters; a wrapped line's continuation is indented by two spaces, and a line that is
    already short enough is kept as it is (a table's row, a blank line)."""
    lines = []
    for line in str(text).splitlines() or [""]:
        if len(line.rstrip()) <= width:
            lines.append(line.rstrip())
            continue
        indent = line[:len(line) - len(line.lstrip())]
        lines.extend(textwrap.wrap(line.strip(), width, initial_indent=indent,
                                   subsequent_indent=indent + "  ", break_on_hyphens=False,
                                   break_long_words=True))
    return "\n".join(lines)


def say(*texts, width: int = PAGE_COLUMNS) -> None:
    """Print ``texts`` (joined by a space, as :func:`print` does) fitted to the page
    (:func:`fit_to_page`)."""
    print(fit_to_page(" ".join(str(t) for t in texts), width))
