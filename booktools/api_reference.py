"""The API reference's pages (``book/api/*.md``) against roughgp's modules: every public
module has an ``automodule`` entry on its subpackage's page (``tests/booktools/
test_api_reference.py``), and :func:`add_missing` writes the entries a new module lacks.

A module is public when no part of its dotted name starts with ``_`` (``roughgp.sampling``'s
``grid_sampler`` is; ``roughgp.__main__`` or a ``_helpers`` module is not). A module's page is
its subpackage's (``roughgp.filling.measured`` -> ``book/api/filling.md``); the package
``roughgp`` itself is on ``index.md``'s table, not documented by autodoc.
"""

from __future__ import annotations

import importlib
import re
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
PACKAGE = ROOT / "roughgp"
API = ROOT / "book" / "api"

_ENTRY = re.compile(r"^\.\. automodule:: ([\w.]+)\s*$", re.MULTILINE)


def public_modules(package: Path = PACKAGE) -> list[str]:
    """The dotted names of roughgp's public modules and subpackages, sorted (from the files:
    nothing is imported)."""
    names = []
    for path in sorted(package.rglob("*.py")):
        parts = path.relative_to(package.parent).with_suffix("").parts
        if parts[-1] == "__init__":
            parts = parts[:-1]
        if len(parts) > 1 and not any(p.startswith("_") for p in parts):
            names.append(".".join(parts))
    return sorted(names)


def documented_modules(api: Path = API) -> dict[str, str]:
    """``{module: page}`` for every ``.. automodule::`` entry of the API pages."""
    return {name: page.name for page in sorted(api.glob("*.md"))
            for name in _ENTRY.findall(page.read_text(encoding="utf-8"))}


def page_of(module: str) -> str:
    """The API page of ``module``: its top-level subpackage's (``roughgp.X...`` -> ``X.md``)."""
    return f"{module.split('.')[1]}.md"


def missing_modules(package: Path = PACKAGE, api: Path = API) -> list[str]:
    """Public modules without an entry on the API pages."""
    documented = documented_modules(api)
    return [m for m in public_modules(package) if m not in documented]


def stale_entries(package: Path = PACKAGE, api: Path = API) -> list[str]:
    """Entries of the API pages that name no module of roughgp (a module removed or renamed)."""
    modules = set(public_modules(package))
    return [m for m in documented_modules(api) if m not in modules]


def entry(module: str) -> str:
    """The Markdown section of one module on its API page."""
    return (f"## `{module}`\n```{{eval-rst}}\n.. automodule:: {module}\n   :members:\n```\n")


_ROLE = re.compile(r":(?:py:)?(?:func|class|meth|mod|attr|data|exc|obj):`~?([^`]*)`")


def broken_references(package: Path = PACKAGE) -> list[str]:
    """Cross-references of roughgp's sources (``:func:`...``` and the like) that Sphinx's
    nitpicky build (``make book``, ``-n``) would not resolve, as ``path:line: target``: a target
    split over two lines, or a ``roughgp.`` target that names no importable module, attribute or
    annotated field."""
    broken = []
    for path in sorted(package.rglob("*.py")):
        text = path.read_text(encoding="utf-8")
        for match in _ROLE.finditer(text):
            target = match.group(1)
            if "<" in target:  # an explicit title: `title <target>`
                target = target[target.index("<") + 1:].rstrip(">")
            line = text.count("\n", 0, match.start()) + 1
            where = f"{path.relative_to(package.parent)}:{line}: {target!r}"
            if re.search(r"\s", target):
                broken.append(where)
            elif target.startswith("roughgp.") and not _defined(target):
                broken.append(where)
    return broken


def _defined(target: str) -> bool:
    """Whether the dotted ``roughgp.`` name is a module or an attribute reachable from one (the
    module is imported: this is what autodoc documents, re-exports included)."""
    parts = target.split(".")
    for cut in range(len(parts), 0, -1):
        try:
            obj = importlib.import_module(".".join(parts[:cut]))
        except ImportError:
            continue
        for name in parts[cut:]:
            if name in getattr(obj, "__annotations__", {}):  # a dataclass field, say
                return True
            if not hasattr(obj, name):
                return False
            obj = getattr(obj, name)
        return True
    return False


def add_missing(package: Path = PACKAGE, api: Path = API) -> list[str]:
    """Insert an entry for every missing module on its page, in alphabetical order among the
    page's sections; returns the modules added."""
    added = missing_modules(package, api)
    for module in added:
        page = api / page_of(module)
        text = page.read_text(encoding="utf-8")
        sections = [(m.start(), m.group(1)) for m in re.finditer(r"^## `([\w.]+)`$", text,
                                                                 re.MULTILINE)]
        after = [start for start, name in sections if name > module]
        at = after[0] if after else len(text)
        block = entry(module) + "\n"
        if not after and not text.endswith("\n\n"):
            block = ("\n" if text.endswith("\n") else "\n\n") + entry(module)
        page.write_text(text[:at] + block + text[at:], encoding="utf-8")
    return added


if __name__ == "__main__":  # python -m booktools.api_reference: add the missing entries
    for name in add_missing():
        print(f"added {name} to book/api/{page_of(name)}")
    for name in stale_entries():
        print(f"stale: {name} (no such module)")
