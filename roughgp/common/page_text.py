"""Text that a chapter prints, fitted to the book's column.

The book's text column (:data:`roughgp.common.page.PAGE_WIDTH_PX`, 688 px) holds
:data:`PAGE_COLUMNS` characters of the theme's monospace font; a longer output line gets a scroll
bar (``booktools.page_fit`` fails a chapter that prints one). :func:`say` prints a sentence or a
report wrapped to that width, with the units the book's figures use: the library's reports write
ASCII units for terminals (``um``, ``um^2``, ``um^4``), the page writes µm, µm², µm⁴
(:func:`book_units`). A table is better shown as a pandas DataFrame (HTML, wrapped by the page).
"""

from __future__ import annotations

import re
import textwrap

PAGE_COLUMNS = 81
"""Characters of a printed line that fit the book's column."""

__all__ = ["PAGE_COLUMNS", "book_units", "fit_to_page", "say"]

_ASCII_UNIT = re.compile(r"\bum(?:\^([234]))?\b")
_SUPERSCRIPT = {None: "", "2": "²", "3": "³", "4": "⁴"}


def book_units(text: str) -> str:
    """``text`` with the unit micrometre written as the book writes it: ``um`` -> µm,
    ``um^2`` -> µm² (and ^3, ^4); other words are left alone."""
    return _ASCII_UNIT.sub(lambda m: "µm" + _SUPERSCRIPT[m.group(1)], text)


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
    """Print ``texts`` (joined by a space, as :func:`print` does) with the book's units
    (:func:`book_units`), fitted to the page (:func:`fit_to_page`)."""
    print(fit_to_page(book_units(" ".join(str(t) for t in texts)), width))
