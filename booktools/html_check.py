"""Scan a built book's HTML for what a reader would see broken: MathJax errors, unresolved roles
(``{glue:text}`...``` printed as text, often inside ``$$ ... $$`` where MyST does not parse
roles) and Sphinx's ``??`` for a reference it could not number.

Two levels:

* :func:`page_faults` reads the static HTML. MathJax typesets in the browser, so the static
  check looks for the TeX that MathJax is known to refuse: ``\\tag`` inside the ``split``
  environment that Sphinx wraps around a display with ``\\\\`` line breaks ("\\tag not allowed in
  split environment"), and two ``\\tag`` in one display ("Multiple \\tag"). Code (``<pre>``,
  ``<code>``) is left out: a role or ``??`` in code is code.
* :func:`mathjax_errors` opens the page in a headless browser (Chromium: ``--dump-dom`` after
  MathJax ran) and reads the errors MathJax itself reports (``data-mjx-error``); it catches every
  MathJax error, at a second or two per page. :func:`wider_than_the_column` renders the page the
  same way, in a window 1280 px wide without scroll bars (the text column is then
  :data:`roughgp.common.page.PAGE_WIDTH_PX`, 688 px), and names each table, image or display
  equation wider than the column (a table a reader must scroll sideways; code blocks are held to
  their characters by the tests instead).

As a Sphinx extension (``sphinx.local_extensions`` in ``book/_config.yml``) :func:`setup` runs
the static scan when the HTML build finishes and reports each fault as a warning, so the book's
``-W`` build fails on it. ``python -m booktools.html_check book/_build/html [--browser chromium]``
runs it on a built book and exits 1 when it finds a fault.
"""

from __future__ import annotations

import argparse
import html as html_module
import re
import shutil
import subprocess
import sys
from pathlib import Path

__all__ = ["page_faults", "mathjax_errors", "wider_than_the_column", "scan", "setup", "main"]

_DROP = re.compile(r"<(script|style|pre|code)\b.*?</\1>", re.S | re.I)
_MATH = re.compile(r'<(div|span) class="math\b[^"]*"[^>]*>(.*?)</\1>', re.S)
_TAG = re.compile(r"<[^>]+>")
_ROLE = re.compile(r"\{(?:glue(?::\w+)?|eq|numref|ref|doc|cite(?::\w+)?|term|math|download)\}`")
_SPLIT = re.compile(r"\\begin\{split\}(.*?)\\end\{split\}", re.S)
_MJX_ERROR = re.compile(r'data-mjx-error="([^"]*)"')
# folders of a build that hold no pages a reader reads
_SKIP = {"_static", "_sources", "_images", "_downloads", "_sphinx_design_static"}


def _text(fragment: str) -> str:
    return " ".join(html_module.unescape(_TAG.sub(" ", fragment)).split())


def page_faults(page: str) -> list[str]:
    """The faults of one page's HTML (``page``, the file's text), each as one line."""
    body = _DROP.sub(" ", page)
    faults = []
    for match in _MATH.finditer(body):
        tex = html_module.unescape(match.group(2))
        short = " ".join(tex.split())[:70]
        if any("\\tag" in block for block in _SPLIT.findall(tex)):
            faults.append(f"MathJax: \\tag not allowed in split environment: {short}")
        if tex.count("\\tag") > 1:
            faults.append(f"MathJax: multiple \\tag: {short}")
        if _ROLE.search(tex):
            faults.append(f"unresolved role in math: {short}")
    text = _text(_MATH.sub(" ", body))
    for match in _ROLE.finditer(text):
        faults.append(f"unresolved role: {text[match.start():match.start() + 60]}")
    for match in re.finditer(r"\?\?", text):
        faults.append(f"'??' (an unresolved reference?): "
                      f"...{text[max(0, match.start() - 40):match.end() + 20]}...")
    return faults


def mathjax_errors(path: Path, browser: str, timeout: float = 60.0) -> list[str]:
    """The errors MathJax reports on the page ``path`` when ``browser`` (a Chromium executable)
    renders it headless, each as ``"MathJax: <message>"``."""
    command = [browser, "--headless", "--no-sandbox", "--disable-gpu",
               "--virtual-time-budget=15000", "--dump-dom", Path(path).resolve().as_uri()]
    done = subprocess.run(command, capture_output=True, text=True, timeout=timeout, check=False)
    if done.returncode != 0:
        raise RuntimeError(f"{browser} could not render {path}: {done.stderr[-500:]}")
    return [f"MathJax: {html_module.unescape(message)}"
            for message in _MJX_ERROR.findall(done.stdout)]


# run in the page once it has loaded and MathJax had time: what is wider than the column
_MEASURE = """<script>
window.addEventListener("load", () => setTimeout(() => {
  const article = document.querySelector("article.bd-article") || document.body;
  const style = getComputedStyle(article);
  const column = article.clientWidth - parseFloat(style.paddingLeft)
                 - parseFloat(style.paddingRight);
  const wide = [];
  for (const el of article.querySelectorAll("table, img, mjx-container[display='true']")) {
    const width = el.getBoundingClientRect().width;
    if (width > column + 1) {
      const what = el.tagName.toLowerCase().replace("mjx-container", "equation");
      const text = (el.innerText || el.getAttribute("alt") || el.getAttribute("src") || "");
      wide.push(`${what} ${Math.round(width)} px: ${text.replace(/\\s+/g, " ").slice(0, 50)}`);
    }
  }
  document.body.setAttribute("data-roughgp-wide",
                             JSON.stringify({column: Math.round(column), wide: wide}));
}, 1000));
</script>
"""
_WIDE = re.compile(r'data-roughgp-wide="([^"]*)"')
_REDIRECT = re.compile(r'<meta http-equiv="Refresh"', re.I)
# Sphinx's own pages (the index of names, the search page): not held to the column
_GENERATED = {"genindex", "search", "py-modindex"}


def wider_than_the_column(path: Path, browser: str, timeout: float = 60.0) -> list[str]:
    """What the page ``path`` shows wider than its text column when ``browser`` (a Chromium
    executable) renders it headless in a window 1280 px wide without scroll bars: each table,
    image and display equation, as ``"wider than the 688 px column: table 923 px: ..."``. The
    page is rendered from a copy beside it with a measuring script added (removed after). A
    redirect (the book's ``index.html``) and Sphinx's generated index and search pages are not
    measured."""
    import json

    path = Path(path)
    text = path.read_text(errors="replace")
    if path.stem in _GENERATED or _REDIRECT.search(text):
        return []
    copy = path.with_name(f".{path.stem}.measure.html")
    copy.write_text(text.replace("</head>", _MEASURE + "</head>", 1))
    try:
        command = [browser, "--headless", "--no-sandbox", "--disable-gpu", "--hide-scrollbars",
                   "--window-size=1280,900", "--virtual-time-budget=15000", "--dump-dom",
                   copy.resolve().as_uri()]
        done = subprocess.run(command, capture_output=True, text=True, timeout=timeout,
                              check=False)
    finally:
        copy.unlink(missing_ok=True)
    found = _WIDE.search(done.stdout)
    if done.returncode != 0 or found is None:
        raise RuntimeError(f"{browser} could not measure {path}: {done.stderr[-500:]}")
    measured = json.loads(html_module.unescape(found.group(1)))
    return [f"wider than the {measured['column']} px column: {item}"
            for item in measured["wide"]]


def pages(html: Path) -> list[Path]:
    """The pages of a built book: every ``.html`` outside the build's static folders."""
    return [page for page in sorted(Path(html).rglob("*.html"))
            if not _SKIP & set(page.relative_to(html).parts)]


def _faults(page: Path, browser: str | None) -> list[str]:
    faults = page_faults(page.read_text(errors="replace"))
    if browser:
        faults += mathjax_errors(page, browser) + wider_than_the_column(page, browser)
    return faults


def scan(html: Path, browser: str | None = None, workers: int = 2) -> dict[str, list[str]]:
    """Page (relative to ``html``) -> its faults, for the pages that have any; with ``browser``
    each page is also rendered (``workers`` browsers at a time): MathJax's own errors and what
    is wider than the column are added."""
    from concurrent.futures import ThreadPoolExecutor

    found_pages = pages(html)
    with ThreadPoolExecutor(max_workers=max(1, workers if browser else 1)) as pool:
        results = list(pool.map(lambda page: _faults(page, browser), found_pages))
    return {str(page.relative_to(html)): faults
            for page, faults in zip(found_pages, results) if faults}


def setup(app):
    """Sphinx extension: after an HTML build, each fault of :func:`page_faults` is a warning."""
    from sphinx.util import logging

    logger = logging.getLogger(__name__)

    def check(app, error):
        if error is not None or app.builder.format != "html":
            return
        for page, faults in scan(Path(app.outdir)).items():
            for fault in faults:
                logger.warning(f"html check: {page}: {fault}", type="roughgp", subtype="html_check")

    app.connect("build-finished", check)
    return {"parallel_read_safe": True, "parallel_write_safe": True}


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(
        prog="python -m booktools.html_check",
        description="Scan a built book for MathJax errors, unresolved roles and '??'.")
    parser.add_argument("html", type=Path, help="the built HTML folder (book/_build/html)")
    parser.add_argument("--browser", help="a Chromium executable: render every page, read "
                                          "MathJax's own errors and find tables, images and "
                                          "equations wider than the column (seconds a page)")
    args = parser.parse_args(argv)
    if not (args.html / "index.html").is_file():
        parser.error(f"html: {args.html} holds no index.html (build the book first)")
    browser = args.browser and (shutil.which(args.browser) or args.browser)
    if browser and not Path(browser).is_file():
        parser.error(f"--browser: {args.browser} was not found")
    found = scan(args.html, browser)
    for page, faults in found.items():
        for fault in faults:
            print(f"{page}: {fault}")
    n_pages = len(pages(args.html))
    print(f"{n_pages} pages scanned, {sum(map(len, found.values()))} faults on {len(found)}")
    return 1 if found else 0


if __name__ == "__main__":
    sys.exit(main())
