"""The package layout: every module imports on its own, imports run one way between the
groups, and no private name is used outside its module (README, "Layout")."""

import ast
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1] / "roughgp"

#: The groups bottom up: a module may import its own group and the groups before it.
LAYERS = ("common", "gp", "sampling", "metrology", "models", "inference", "beyond",
          "experiments", "ledger", "cli")


def _modules():
    for path in sorted(ROOT.rglob("*.py")):
        parts = path.relative_to(ROOT.parent).with_suffix("").parts
        yield ".".join(parts[:-1] if parts[-1] == "__init__" else parts), path


MODULES = dict(_modules())


def _group(module: str) -> str | None:
    parts = module.split(".")
    return parts[1] if len(parts) > 1 else None


def _imports(path: Path):
    """(imported roughgp module, names, line) for every import in the file, local ones too."""
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
            if node.module == "roughgp" or node.module.startswith("roughgp."):
                yield node.module, [a.name for a in node.names], node.lineno
        elif isinstance(node, ast.Import):
            for a in node.names:
                if a.name.startswith("roughgp"):
                    yield a.name, [], node.lineno


def test_every_module_is_in_a_group():
    for module in MODULES:
        group = _group(module)
        assert group is None or group in LAYERS, f"{module} is in no group of {LAYERS}"


_FRESH_IMPORTS = r"""
import os, sys, traceback
import numpy, scipy, scipy.linalg, scipy.optimize, scipy.stats, torch, gpytorch, matplotlib
matplotlib.use("Agg")
failed = []
for module in sys.argv[1:]:
    read, write = os.pipe()
    pid = os.fork()
    if pid == 0:  # a child with no roughgp module imported yet
        os.close(read)
        try:
            __import__(module)
            os._exit(0)
        except BaseException:
            os.write(write, traceback.format_exc()[-1500:].encode())
            os._exit(1)
    os.close(write)
    message = os.read(read, 4096).decode()
    os.close(read)
    _, status = os.waitpid(pid, 0)
    if status != 0:
        failed.append(f"{module}: {message}")
print("\n".join(failed))
sys.exit(1 if failed else 0)
"""


def test_every_module_imports_on_its_own():
    """Each module imported first, in a fresh interpreter state (a forked child that has the
    third-party libraries but no roughgp module loaded): no cycle, no order dependence."""
    result = subprocess.run([sys.executable, "-c", _FRESH_IMPORTS, *sorted(MODULES)],
                            capture_output=True, text=True, timeout=600)
    assert result.returncode == 0, result.stdout[-4000:] + result.stderr[-2000:]


def test_imports_run_one_way():
    wrong = []
    for module, path in MODULES.items():
        group = _group(module)
        if group is None:
            continue
        for target, names, line in _imports(path):
            targets = [target] if target != "roughgp" else [f"roughgp.{n}" for n in names]
            for t in targets:
                tg = _group(t)
                if tg in LAYERS and LAYERS.index(tg) > LAYERS.index(group):
                    wrong.append(f"{path.relative_to(ROOT.parent)}:{line}: {group} imports {t}")
    assert not wrong, "imports against the layers:\n" + "\n".join(wrong)


def test_no_private_name_crosses_a_module():
    crossing = []
    for module, path in MODULES.items():
        tree = ast.parse(path.read_text(encoding="utf-8"))
        aliases = set()
        for target, names, line in _imports(path):
            private = [n for n in names if n.startswith("_") and not n.startswith("__")]
            if private:
                crossing.append(f"{module}:{line}: imports {private} from {target}")
        for node in ast.walk(tree):
            if isinstance(node, ast.ImportFrom) and node.module and \
                    node.module.startswith("roughgp"):
                aliases |= {a.asname or a.name for a in node.names}
            elif isinstance(node, ast.Import):
                aliases |= {a.asname or a.name.split(".")[0] for a in node.names
                            if a.name.startswith("roughgp")}
        for node in ast.walk(tree):
            if isinstance(node, ast.Attribute) and isinstance(node.value, ast.Name) and \
                    node.value.id in aliases and node.attr.startswith("_") and \
                    not node.attr.startswith("__"):
                crossing.append(f"{module}:{node.lineno}: uses {node.value.id}.{node.attr}")
    assert not crossing, "\n".join(crossing)


def test_no_module_is_over_500_lines():
    long = {m: n for m, p in MODULES.items()
            if (n := len(p.read_text(encoding="utf-8").splitlines())) > 500}
    assert not long, f"modules over 500 lines: {long}"


def test_the_readme_layout_names_every_group():
    readme = (ROOT.parent / "README.md").read_text(encoding="utf-8")
    for group in LAYERS:
        assert f"roughgp/{group}/" in readme, f"README's layout misses roughgp/{group}/"


def test_tests_mirror_the_packages():
    tests = Path(__file__).resolve().parent
    folders = {p.name for p in tests.iterdir() if p.is_dir() and not p.name.startswith(("_", "."))}
    # tests/booktools/ tests what builds the book (booktools/), which is no part of roughgp
    groups = set(LAYERS) | {"booktools"}
    assert folders <= groups, f"test folders that are no group: {folders - groups}"
    assert {g for g in LAYERS if g != "common"} <= folders | {"common"}
