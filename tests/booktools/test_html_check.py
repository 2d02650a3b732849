"""The HTML scan of a built book (booktools/html_check.py): it finds the faults readers met
(notation's eq 18 "\\tag not allowed in split environment", ground's ``{glue:text}`` inside
``$$``, Sphinx's ``??``), on hand-written pages and on a tiny book built by jupyter-book, and
stays quiet on the same pages written correctly."""

import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from booktools import html_check

ROOT = Path(__file__).resolve().parents[2]
BROWSER = shutil.which("chromium") or shutil.which("chromium-browser")

_CLEAN = """<html><body><p>The ACVF of eq <a href="#eq18">(18)</a>.</p>
<div class="math notranslate nohighlight">\\[\\begin{equation*}a = \\begin{pmatrix}1 \\\\ 2
\\end{pmatrix}\\tag{18}\\end{equation*}\\]</div>
<pre>print("what?? {glue:text}`x`")</pre><p>Sal &#8776; 3.14 µm.</p></body></html>"""


def test_a_clean_page_has_no_fault():
    assert html_check.page_faults(_CLEAN) == []


@pytest.mark.parametrize("fragment, fault", [
    ('<div class="math notranslate nohighlight">\\[\\begin{split}a = b \\\\ c\\tag{18}'
     '\\end{split}\\]</div>', "\\tag not allowed in split"),
    ('<div class="math notranslate nohighlight">\\[Sal \\approx {glue:text}`sal:.2f`\\]</div>',
     "unresolved role in math"),
    ('<div class="math">\\[a \\tag{1} \\\\ b \\tag{2}\\]</div>', "multiple \\tag"),
    ("<p>as in figure <span>??</span>.</p>", "'??'"),
    ("<p>the fit gives {glue:text}`value` here</p>", "unresolved role:"),
])
def test_each_fault_is_found(fragment, fault):
    faults = html_check.page_faults(_CLEAN.replace("</body>", fragment + "</body>"))
    assert len(faults) == 1 and fault in faults[0], faults


_BAD_PAGE = """# Equations

$$
r = \\begin{pmatrix}a & b\\\\ c & d\\end{pmatrix}
\\tag{18}
$$

Figure ?? and
$$
Sal \\approx {glue:text}`sal_predicted:.2f`
$$
"""

_GOOD_PAGE = """# Equations

\\begin{equation*}
r = \\begin{pmatrix}a & b\\\\ c & d\\end{pmatrix}
\\tag{18}
\\end{equation*}

Sal is about 3.
"""


def _book(root, page):
    root.mkdir()
    (root / "_config.yml").write_text(
        "title: tiny\nonly_build_toc_files: true\nexecute:\n  execute_notebooks: 'off'\n"
        "parse:\n  myst_enable_extensions: [dollarmath, amsmath]\n"
        "sphinx:\n  extra_extensions: [sphinx-mathjax-offline]\n"
        f"  local_extensions:\n    html_check: {ROOT / 'booktools'}\n")
    (root / "_toc.yml").write_text("format: jb-book\nroot: page\n")
    (root / "page.md").write_text(page)
    done = subprocess.run([str(Path(sys.executable).with_name("jupyter-book")), "build", "-W",
                           "--keep-going", "--path-output", str(root), str(root)],
                          capture_output=True, text=True, check=False)
    return done, root / "_build" / "html"


def test_the_book_build_fails_on_the_faults_and_passes_without_them(tmp_path):
    done, html = _book(tmp_path / "bad", _BAD_PAGE)
    faults = html_check.scan(html)["page.html"]
    assert any("\\tag not allowed in split" in f for f in faults), faults
    assert any("unresolved role in math" in f for f in faults), faults
    assert any("'??'" in f for f in faults), faults
    assert done.returncode != 0 and "html check: page.html: MathJax" in done.stdout + done.stderr
    done, html = _book(tmp_path / "good", _GOOD_PAGE)
    assert done.returncode == 0, done.stdout[-2000:] + done.stderr[-2000:]
    assert html_check.scan(html) == {}
    assert html_check.main([str(html)]) == 0


@pytest.mark.skipif(BROWSER is None, reason="no Chromium on this machine")
def test_the_browser_reads_mathjax_own_errors(tmp_path):
    """MathJax itself (the book's local copy, in headless Chromium) refuses the notation
    chapter's old eq 18 and typesets the new one."""
    _, html = _book(tmp_path / "bad", _BAD_PAGE)
    errors = html_check.mathjax_errors(html / "page.html", BROWSER)
    assert any("not allowed in split" in e for e in errors), errors
    _, html = _book(tmp_path / "good", _GOOD_PAGE)
    assert html_check.mathjax_errors(html / "page.html", BROWSER) == []


def test_the_command_refuses_a_folder_without_a_book(tmp_path, capsys):
    with pytest.raises(SystemExit) as info:
        html_check.main([str(tmp_path)])
    assert info.value.code == 2 and "holds no index.html" in capsys.readouterr().err


@pytest.mark.skipif(BROWSER is None, reason="no Chromium on this machine")
def test_the_browser_finds_a_table_wider_than_the_column(tmp_path):
    """A table of 14 long columns runs past the 688 px column; one of three does not."""
    wide = "| " + " | ".join(f"column number {k}" for k in range(14)) + " |\n" \
        + "|" + "---|" * 14 + "\n| " + " | ".join("1.234567" for _ in range(14)) + " |\n"
    narrow = "| a | b | c |\n|---|---|---|\n| 1 | 2 | 3 |\n"
    _, html = _book(tmp_path / "wide", "# Tables\n\n" + wide)
    found = html_check.wider_than_the_column(html / "page.html", BROWSER)
    assert len(found) == 1 and found[0].startswith("wider than the 688 px column: table")
    _, html = _book(tmp_path / "narrow", "# Tables\n\n" + narrow)
    assert html_check.wider_than_the_column(html / "page.html", BROWSER) == []
