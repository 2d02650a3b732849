"""The package layout: every module imports on its own, imports run one way between the
groups, no circle of imports among the modules, and no private name is used outside its module
(README, "Where things are")."""

import ast
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1] / "roughgp"

#: The groups bottom up: a module may import its own group and the groups before it.
LAYERS = ("common", "gp", "sampling", "io", "metrology", "models", "non_gaussian", "targets",
          "inference", "filling", "surface_models", "checking", "api", "batch", "experiments",
          "ledger", "cli")


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


def import_graph(modules=None) -> dict:
    """``{module: {modules it imports}}`` over the modules that are no package face, local
    imports included: ``from roughgp.a.b import c`` is an arrow to ``roughgp.a.b.c`` where that
    is a module, else to ``roughgp.a.b``; an import of a face (``from roughgp.sampling import
    sample_grid``) is no arrow (package faces aside)."""
    modules = MODULES if modules is None else modules
    faces = {m for m, p in modules.items() if p.name == "__init__.py"}
    graph = {}
    for module, path in modules.items():
        if module in faces:
            continue
        arrows = set()
        for target, names, _ in _imports(path):
            for t in (target, *(f"{target}.{n}" for n in names)):
                if t in modules and t not in faces and t != module:
                    arrows.add(t)
        graph[module] = arrows
    return graph


def circles(graph) -> list:
    """The circles of ``graph``: its strongly connected components of more than one module
    (Tarjan), each sorted."""
    index, low, stack, on, found = {}, {}, [], set(), []

    def visit(v):
        index[v] = low[v] = len(index)
        stack.append(v)
        on.add(v)
        for w in sorted(graph[v]):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            component = []
            while True:
                w = stack.pop()
                on.discard(w)
                component.append(w)
                if w == v:
                    break
            if len(component) > 1:
                found.append(sorted(component))

    for v in sorted(graph):
        if v not in index:
            visit(v)
    return found


def test_no_circle_of_imports_among_the_modules():
    """Not only between the groups: no two modules of roughgp import each other, directly or
    round a longer loop, at the top or inside a function."""
    found = circles(import_graph())
    assert not found, "import circles:\n" + "\n".join(" -> ".join(c) for c in found)


def test_a_circle_is_found(tmp_path):
    package = tmp_path / "roughgp"
    for name, text in {"__init__.py": "", "a/__init__.py": "from roughgp.a.x import f\n",
                       "a/x.py": "from roughgp.a import y\n",
                       "a/y.py": "def g():\n    from roughgp.a.z import h\n",
                       "a/z.py": "from roughgp.a.x import f\n",
                       "a/w.py": "from roughgp.a import x\n"}.items():
        (package / name).parent.mkdir(parents=True, exist_ok=True)
        (package / name).write_text(text)
    modules = {}
    for path in sorted(package.rglob("*.py")):
        parts = path.relative_to(tmp_path).with_suffix("").parts
        modules[".".join(parts[:-1] if parts[-1] == "__init__" else parts)] = path
    assert circles(import_graph(modules)) == [["roughgp.a.x", "roughgp.a.y", "roughgp.a.z"]]


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


def test_every_module_compiles_without_a_warning():
    """An invalid escape in a docstring (``\\ell`` written ``\ell``) is a SyntaxWarning on
    import today and an error in a later Python; it also reaches a user's terminal as a stray
    ``warning:`` line from a command that compiles the module on first use."""
    import warnings
    noisy = {}
    for module, path in MODULES.items():
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            compile(path.read_text(encoding="utf-8"), str(path), "exec")
        if caught:
            noisy[module] = str(caught[0].message)
    assert not noisy, f"modules that compile with a warning: {noisy}"


def test_the_readme_layout_names_every_group():
    readme = (ROOT.parent / "README.md").read_text(encoding="utf-8")
    for group in LAYERS:
        where = f"roughgp/{group}/" if (ROOT / group).is_dir() else f"roughgp/{group}.py"
        assert where in readme, f"README's layout misses {where}"


def test_tests_mirror_the_packages():
    tests = Path(__file__).resolve().parent
    folders = {p.name for p in tests.iterdir() if p.is_dir() and not p.name.startswith(("_", "."))}
    # tests/booktools/ tests what builds the book (booktools/), which is no part of roughgp
    groups = set(LAYERS) | {"booktools"}
    assert folders <= groups, f"test folders that are no group: {folders - groups}"
    assert {g for g in LAYERS if g != "common"} <= folders | {"common"}
