"""The repository's front matter: a README a newcomer reads in two minutes, a LICENSE that is the
licence pyproject.toml declares, a CITATION.cff that cites the project and the paper, and a
landing page that links every page of the book."""

import re
import tomllib
from pathlib import Path

import yaml

ROOT = Path(__file__).resolve().parents[2]


def test_the_readme_is_short_and_points_to_the_rest():
    text = (ROOT / "README.md").read_text(encoding="utf-8")
    # under 115 lines: 100 until its code blocks were laid out for the book's 81-column
    # page (tests/test_book_pages.py), each command's comment on a line of its own
    assert len(text.splitlines()) < 115
    for needed in ("make book", "make test", "book/images/surfaces.png", "book/running.md",
                   "API reference", "LICENSE", "CITATION.cff"):
        assert needed in text, needed
    assert (ROOT / "book" / "images" / "surfaces.png").is_file()
    commands = re.findall(r"^roughgp \w+", text, re.M)
    assert len(commands) == 5, commands


def test_the_licence_file_is_the_declared_licence():
    declared = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]["license"]["text"]
    assert declared == "MIT"
    assert (ROOT / "LICENSE").read_text().startswith("MIT License")


def test_the_citation_file_cites_the_project_and_the_paper():
    cff = yaml.safe_load((ROOT / "CITATION.cff").read_text(encoding="utf-8"))
    assert cff["cff-version"] == "1.2.0" and cff["type"] == "software"
    assert cff["license"] == "MIT"
    paper = cff["references"][0]
    assert paper["title"] == "Model of rough surfaces with Gaussian processes"
    assert [a["family-names"] for a in paper["authors"]] == ["Jawaid", "Seewig"]


def _toc_files(node):
    if isinstance(node, dict):
        if "file" in node:
            yield node["file"]
        for value in node.values():
            yield from _toc_files(value)
    elif isinstance(node, list):
        for value in node:
            yield from _toc_files(value)


def test_the_landing_page_links_every_chapter_and_lab():
    toc = yaml.safe_load((ROOT / "book" / "_toc.yml").read_text())
    intro = (ROOT / "book" / "intro.md").read_text(encoding="utf-8")
    linked = set(re.findall(r"\{doc\}`([^`<]+)`", intro))
    pages = [f for f in _toc_files(toc["parts"]) if not f.startswith(("api/", "labs/"))]
    missing = [f for f in pages if f not in linked and f != "api/index"]
    assert not missing, f"the landing page does not link {missing}"
    labs = [f for f in _toc_files(toc["parts"]) if f.startswith("labs/")]
    on_disk = sorted(f"labs/{p.stem}" for p in (ROOT / "notebooks").glob("lab*.ipynb"))
    assert sorted(labs) == on_disk, "every lab of notebooks/ in the table of contents"
    assert {labs[0], labs[-1]} <= linked
