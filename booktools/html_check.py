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
  MathJax error, at a second or two per page.

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

__all__ = ["page_faults", "mathjax_errors", "scan", "setup", "main"]

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


def pages(html: Path) -> list[Path]:
    """The pages of a built book: every ``.html`` outside the build's static folders."""
    return [page for page in sorted(Path(html).rglob("*.html"))
            if not _SKIP & set(page.relative_to(html).parts)]


def scan(html: Path, browser: str | None = None) -> dict[str, list[str]]:
    """Page (relative to ``html``) -> its faults, for the pages that have any; with ``browser``
    each page is also rendered and MathJax's own errors are added."""
    found = {}
    for page in pages(html):
        faults = page_faults(page.read_text(errors="replace"))
        if browser:
            faults += mathjax_errors(page, browser)
        if faults:
            found[str(page.relative_to(html))] = faults
    return found


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
    parser.add_argument("--browser", help="a Chromium executable: render every page and read "
                                          "MathJax's own errors too (a second or two a page)")
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
