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
