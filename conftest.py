"""pytest: every notebook run (nbmake's items for book/ and notebooks/) carries the marker
``notebook``, so ``pytest -m "not notebook"`` runs the unit tier alone."""

import pytest


def pytest_collection_modifyitems(items):
    for item in items:
        if str(item.path).endswith(".ipynb"):
            item.add_marker(pytest.mark.notebook)
