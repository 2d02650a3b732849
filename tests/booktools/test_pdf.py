"""``make pdf`` (booktools/pdf.py): a book built as one page and printed by headless Chromium
to a PDF, offline, with its equations typeset by the book's local MathJax. The tiny book has a
sphinx-design card and sphinx-exercise, as the book has: without the module's Sphinx extension
its one-page build stops at "unknown node type" (sphinx-exercise registers nodes for
``singlehtml``, and Sphinx then ignores the handlers registered for ``html``)."""

import re
import shutil

import pytest

from booktools import pdf
_PAGE = """# Equations

\\begin{equation*}
r = \\begin{pmatrix}a & b\\\\ c & d\\end{pmatrix}
\\tag{18}
\\end{equation*}
"""

BROWSER = pdf.browser()


def _tiny_book(root):
    root.mkdir()
    (root / "_config.yml").write_text(
        "title: tiny\nonly_build_toc_files: true\nexecute:\n  execute_notebooks: 'off'\n"
        "parse:\n  myst_enable_extensions: [dollarmath, amsmath, colon_fence]\n"
        "sphinx:\n  extra_extensions: [sphinx-mathjax-offline, sphinx_exercise]\n"
        f"  local_extensions:\n    pdf: {pdf.ROOT / 'booktools'}\n")
    (root / "_toc.yml").write_text("format: jb-book\nroot: page\nchapters:\n- file: second\n")
    (root / "page.md").write_text(_PAGE)
    (root / "second.md").write_text("# Second page\n\nThe second chapter, $\\sigma^2$.\n\n"
                                    "::::{grid} 1 1 2 2\n\n:::{grid-item-card} A card title\n"
                                    "Its text.\n:::\n\n::::\n")
    return root


@pytest.mark.skipif(BROWSER is None, reason="no Chromium on this machine")
def test_a_book_becomes_one_pdf(tmp_path):
    page = pdf.build_single_page(_tiny_book(tmp_path / "book"))
    html = page.read_text()
    assert "Second page" in html and "Equations" in html    # both chapters on one page
    assert "A card title" in html   # sphinx-design's card, written by the singlehtml builder
    out = pdf.print_to_pdf(page, tmp_path / "out" / "book.pdf", BROWSER)
    data = out.read_bytes()
    assert data.startswith(b"%PDF-") and len(re.findall(rb"/Type\s*/Page\b", data)) >= 1
    assert "print" in (page.with_name("print.html").read_text())  # the print rules added


def test_without_chromium_the_command_says_what_to_install(monkeypatch, capsys):
    monkeypatch.setattr(shutil, "which", lambda name: None)
    assert pdf.main([]) == 2
    assert "apt-get install chromium" in capsys.readouterr().err
