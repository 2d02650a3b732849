"""One regressed claim does not erase the book (issue 43).

With one claim forced to regress (``ROUGHGP_LEDGER_FAULT``, on the one quick claim that
``ROUGHGP_LEDGER_ONLY`` leaves to run) the chapter "Claims ledger" runs to its end; its nbmake
test item fails naming the claim (``pytest --nbmake`` through this repository's conftest.py),
when executed and again when its run comes from the notebook cache; the book built after that
failing test run, as ``make book`` after a failing ``make test``, takes the chapter from the
cache, writes every page and shows the claim in red, and its execution-status page lists the
chapter. ``roughgp reproduce`` exits 1 on the same fault (tests/ledger/test_fault_injection.py).

It all runs in a copy: ``conftest.py`` and ``booktools/`` (whose notebook cache then lies in the
copy's ``book/_build``), the real chapter, the real execution-status page and the book's
configuration, with one-line stand-ins for the pages the chapter links to. The tests' and the
book's real cache is not touched. About half a minute."""

import os
import shutil
import subprocess
import sys
from pathlib import Path

import nbformat
import pytest
import yaml

from roughgp.ledger.runner import FAULT_ENV, FAULT_MARK, ONLY_ENV

ROOT = Path(__file__).resolve().parents[2]
BOOK = ROOT / "book"
KEY = "eq5-duality"   # its check takes seconds


def _stand_in(path):
    """A page the chapter links to, without code (the build does not execute it)."""
    title = f"# {path.stem} (stand-in)\n"
    if path.suffix == ".md":
        path.write_text(title)
        return
    nb = nbformat.v4.new_notebook()
    nb.metadata["kernelspec"] = {"name": "python3", "display_name": "Python 3",
                                 "language": "python"}
    nb.cells = [nbformat.v4.new_markdown_cell(title)]
    nbformat.write(nb, path)


def _repository(repo):
    """``repo``: conftest.py, booktools/ and a book of the chapter, the execution page and
    stand-ins for every other chapter and ``running.md``, with the book's configuration (its
    extensions, the copied ones, and -W checks included). Returns the book and its pages."""
    repo.mkdir()
    shutil.copy(ROOT / "conftest.py", repo / "conftest.py")
    shutil.copytree(ROOT / "booktools", repo / "booktools",
                    ignore=shutil.ignore_patterns("__pycache__"))
    book = repo / "book"
    book.mkdir()
    for name in ("claims.ipynb", "execution.md", "references.bib"):
        shutil.copy(BOOK / name, book / name)
    stand_ins = [p.name for p in sorted(BOOK.glob("*.ipynb")) if p.name != "claims.ipynb"]
    for name in stand_ins + ["running.md"]:
        _stand_in(book / name)
    config = yaml.safe_load((BOOK / "_config.yml").read_text())
    config["execute"]["exclude_patterns"] = stand_ins
    sphinx = config["sphinx"]
    sphinx["local_extensions"] = {name: str(repo / "booktools")
                                  for name in sphinx["local_extensions"]}
    (book / "_config.yml").write_text(yaml.safe_dump(config, sort_keys=False))
    chapters = ["execution", "running"] + [Path(n).stem for n in stand_ins]
    (book / "_toc.yml").write_text(yaml.safe_dump(
        {"format": "jb-book", "root": "claims", "chapters": [{"file": c} for c in chapters]},
        sort_keys=False))
    return book, ["claims"] + chapters


@pytest.fixture(scope="module")
def faulty(tmp_path_factory):
    """Two test runs of the chapter with the fault (executed, then from the cache), then the
    book built: ``(test runs, build, html folder, pages)``."""
    repo = tmp_path_factory.mktemp("regressed") / "repo"
    book, pages = _repository(repo)
    env = {**os.environ, ONLY_ENV: KEY, FAULT_ENV: KEY}
    env.pop("ROUGHGP_FULL", None)
    bin_dir = Path(sys.executable).parent
    tests = [subprocess.run([sys.executable, "-m", "pytest", "--nbmake", "book/claims.ipynb",
                             "-p", "no:cacheprovider", "-q", "-W", "ignore"],
                            cwd=repo, env=env, capture_output=True, text=True, check=False)
             for _ in range(2)]
    build = subprocess.run([str(bin_dir / "jupyter-book"), "build", "-W", "-n", "--keep-going",
                            str(book)], env=env, capture_output=True, text=True, check=False)
    return tests, build, book / "_build" / "html", pages


def test_the_claims_test_item_fails_naming_the_claim_executed_and_cached(faulty):
    tests, _, _, _ = faulty
    for test, how in zip(tests, ("executed", "cached")):
        out = test.stdout + test.stderr
        assert test.returncode == 1, out[-3000:]
        assert "1 regressed claim(s)" in out and "these checks no longer give their verdict" in out
        assert f"\n  {KEY}: " in out and FAULT_MARK in out
        assert f"notebook book/claims.ipynb: failed {how}" in out, out[-3000:]


def test_the_book_writes_every_page_and_shows_the_regression_in_red(faulty):
    _, build, html, pages = faulty
    log = build.stdout + build.stderr
    assert build.returncode == 0, log[-3000:]
    assert "Using cached notebook" in log and "Executed notebook" not in log, \
        "the book renders the run the tests stored"
    for page in pages:
        assert (html / f"{page}.html").is_file(), page
    text = (html / "claims.html").read_text()
    notice = text[text.index("A claim regressed"):]
    # a red (error) admonition, above the ledger's table
    assert text.index('class="error admonition"') < text.index("A claim regressed") \
        < text.index('id="the-ledger"')
    assert KEY in notice[:3000] and FAULT_MARK in notice[:3000]
    # red badges: two in the notice, the table's status, the details' status
    assert text.count("sd-badge sd-bg-danger") == 4
    assert "REGRESSED" in text and "the build stops" not in text


def test_the_execution_page_lists_the_chapter_from_the_cache(faulty):
    _, build, html, _ = faulty
    assert build.returncode == 0
    text = (html / "execution.html").read_text()
    row = text[text.index("<tbody>"):]
    row = row[row.index('href="claims.html"'):]
    row = row[:row.index("</tr>")]
    assert ">cache<" in row and "✅" in row
