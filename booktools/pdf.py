"""The book as one PDF, offline: ``make pdf`` (``python -m booktools.pdf``).

Jupyter Book 1.x makes a PDF in two ways, neither of them offline here: ``--builder pdflatex``
needs a TeX installation, and ``--builder pdfhtml`` prints with Playwright's own Chromium, which
it downloads. This module does what ``pdfhtml`` does with the Chromium of the system: it builds
the book as one HTML page (``--builder singlehtml``, the notebooks from the same cache as
``make book``, so after ``make test`` or ``make book`` nothing is executed again), adds the same
print rules as ``pdfhtml`` (a cell's input or output is not split across pages), and prints that
page with headless Chromium (``--print-to-pdf``), giving MathJax (served locally,
``sphinx-mathjax-offline``) time to typeset. The PDF is ``book/_build/pdf/book.pdf``.

As a Sphinx extension (``local_extensions`` in ``book/_config.yml``) :func:`setup` gives the
``singlehtml`` translator the node handlers that extensions register for ``html`` only
(sphinx-design's card titles, myst-nb's hidden code cells): without them the one-page build
stops at "unknown node type".

Chromium is not part of the Python environment: on Debian it is the package ``chromium``
(``apt-get install chromium``); :func:`main` says so when it finds none.
"""

from __future__ import annotations

import argparse
import re
import shutil
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
BOOK = ROOT / "book"
PDF = BOOK / "_build" / "pdf" / "book.pdf"
BROWSERS = ("chromium", "chromium-browser", "google-chrome", "google-chrome-stable")
# milliseconds of page time Chromium gives scripts (MathJax) before it prints
TYPESET_BUDGET_MS = 120_000

# jupyter_book.pdf's print rules: a cell's input or output stays on one page; and the print
# shows the article alone (no sidebars, no header buttons)
PRINT_CSS = """<style media="print">
div.cell_input, div.cell_output { break-inside: avoid; page-break-inside: avoid; }
.bd-sidebar-primary, .bd-sidebar-secondary, .bd-header-article, .bd-header,
.bd-footer, .prev-next-area, .header-article-items { display: none !important; }
.bd-main .bd-content .bd-article-container { max-width: 100% !important; }
</style>
"""

__all__ = ["PDF", "browser", "build_single_page", "print_to_pdf", "main", "setup"]


def browser() -> str | None:
    """The path of a Chromium (or Chrome) on the PATH; None when there is none."""
    for name in BROWSERS:
        found = shutil.which(name)
        if found:
            return found
    return None


def build_single_page(book: Path = BOOK) -> Path:
    """Build ``book`` as one HTML page (jupyter-book's ``singlehtml`` builder, warnings as
    errors, as ``make book``, into ``book/_build/singlehtml``); returns that page (the book's
    root page: ``index.html`` redirects to it). Raises CalledProcessError when the build fails."""
    jupyter_book = Path(sys.executable).with_name("jupyter-book")
    subprocess.run([str(jupyter_book), "build", "-W", "-n", "--keep-going",
                    "--builder", "singlehtml", "--path-output", str(book), str(book)],
                   check=True)
    index = book / "_build" / "singlehtml" / "index.html"
    redirect = re.search(r'http-equiv="Refresh" content="0; url=([^"]+)"', index.read_text())
    return index.with_name(redirect.group(1)) if redirect else index


def print_to_pdf(page: Path, pdf: Path, chromium: str, timeout: float = 900) -> Path:
    """Print the HTML ``page`` to ``pdf`` with headless ``chromium``, with :data:`PRINT_CSS`
    added (in a copy of the page beside it, so its relative links resolve). Raises
    RuntimeError when Chromium writes no PDF."""
    html = page.read_text(encoding="utf-8")
    printable = page.with_name("print.html")
    printable.write_text(html.replace("</head>", PRINT_CSS + "</head>", 1), encoding="utf-8")
    pdf.parent.mkdir(parents=True, exist_ok=True)
    pdf.unlink(missing_ok=True)
    run = subprocess.run(
        [chromium, "--headless", "--no-sandbox", "--disable-gpu", "--no-pdf-header-footer",
         f"--virtual-time-budget={TYPESET_BUDGET_MS}", "--run-all-compositor-stages-before-draw",
         f"--print-to-pdf={pdf}", printable.resolve().as_uri()],
        capture_output=True, text=True, timeout=timeout)
    if not pdf.exists() or pdf.read_bytes()[:5] != b"%PDF-":
        raise RuntimeError(f"Chromium wrote no PDF (exit {run.returncode}):\n{run.stderr[-2000:]}")
    return pdf


def _share_html_handlers(app) -> None:
    """For the ``singlehtml`` builder: every node handler registered for ``html`` that
    ``singlehtml`` lacks (Sphinx looks up a builder's handlers by its name first, and falls back
    to its format only when that name has none)."""
    if app.builder.name != "singlehtml":
        return
    handlers = app.registry.translation_handlers
    single = handlers.setdefault("singlehtml", {})
    for node, pair in handlers.get("html", {}).items():
        single.setdefault(node, pair)


def setup(app):
    """Sphinx extension: the ``singlehtml`` build writes every node the ``html`` build writes
    (see the module's docstring)."""
    app.connect("builder-inited", _share_html_handlers)
    return {"parallel_read_safe": True, "parallel_write_safe": True}


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(prog="python -m booktools.pdf", description=__doc__.split(
        "\n\n")[0])
    parser.add_argument("--out", type=Path, default=PDF, help=f"the PDF to write ({PDF})")
    args = parser.parse_args(argv)
    chromium = browser()
    if chromium is None:
        print("make pdf: the book is printed to PDF with Chromium, and none is installed "
              "(on Debian: apt-get install chromium)", file=sys.stderr)
        return 2
    page = build_single_page()
    pdf = print_to_pdf(page, args.out, chromium)
    print(f"pdf: {pdf} ({pdf.stat().st_size / 1e6:.1f} MB)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
