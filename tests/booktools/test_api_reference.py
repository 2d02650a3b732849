"""Every public module of roughgp has an entry in the API reference (book/api/*.md), on its
subpackage's page, and every entry names a module that exists."""

from __future__ import annotations

from booktools import api_reference as api


def test_every_public_module_has_an_entry_in_the_api_reference():
    missing = api.missing_modules()
    assert not missing, (
        "no entry in book/api/*.md for: " + ", ".join(missing)
        + " (python -m booktools.api_reference adds them to their subpackage's page)")


def test_every_entry_names_a_module_on_its_subpackages_page():
    assert not api.stale_entries(), f"entries naming no module: {api.stale_entries()}"
    wrong = {m: page for m, page in api.documented_modules().items() if page != api.page_of(m)}
    assert not wrong, f"modules on another subpackage's page: {wrong}"


def test_a_new_module_without_an_entry_is_named_and_then_added(tmp_path):
    package = tmp_path / "roughgp"
    for name in ("__init__.py", "common/__init__.py", "common/old.py", "common/new.py",
                 "common/_private.py", "gp/__init__.py"):
        (package / name).parent.mkdir(parents=True, exist_ok=True)
        (package / name).write_text("")
    pages = tmp_path / "api"
    pages.mkdir()
    (pages / "common.md").write_text("# Common\n\n" + api.entry("roughgp.common") + "\n"
                                     + api.entry("roughgp.common.old"))
    (pages / "gp.md").write_text("# GP\n\n" + api.entry("roughgp.gp"))
    assert api.missing_modules(package, pages) == ["roughgp.common.new"]
    assert api.add_missing(package, pages) == ["roughgp.common.new"]
    assert api.missing_modules(package, pages) == []
    text = (pages / "common.md").read_text()
    assert text.index("roughgp.common.new") < text.index("roughgp.common.old")


def test_every_cross_reference_of_the_sources_names_something():
    broken = api.broken_references()
    assert not broken, "cross-references make book -n would not resolve: " + "; ".join(broken)


def test_a_reference_split_over_two_lines_or_naming_nothing_is_found(tmp_path):
    package = tmp_path / "roughgp"
    package.mkdir()
    (package / "mod.py").write_text(
        '"""See :func:`~roughgp.checking.\n    ranks.rank_counts`, '
        ':func:`roughgp.sampling.no_such_function`, :class:`roughgp.sampling.SamplingInfo` '
        'and :func:`numpy.fft.rfft`."""\n')
    assert api.broken_references(package) == [
        "roughgp/mod.py:1: 'roughgp.checking.\\n    ranks.rank_counts'",
        "roughgp/mod.py:2: 'roughgp.sampling.no_such_function'"]


def test_every_api_page_is_in_the_table_of_contents_and_the_index():
    """A subpackage's page is reachable: a section of book/_toc.yml and a row of the index's
    table (no page of a package that is gone)."""
    toc = (api.ROOT / "book" / "_toc.yml").read_text(encoding="utf-8")
    index = (api.API / "index.md").read_text(encoding="utf-8")
    pages = {p.stem for p in api.API.glob("*.md")} - {"index"}
    assert pages == {api.page_of(m)[:-3] for m in api.public_modules()}
    for page in sorted(pages):
        assert f"file: api/{page}\n" in toc, f"book/_toc.yml misses api/{page}"
        assert f"{{doc}}`{page}`" in index, f"book/api/index.md's table misses {page}"
