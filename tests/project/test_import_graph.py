"""The package's import structure (the Python twin of csrc/tools/check_calls.sh).

Read from the source with ``ast`` (nothing is imported): every ``import`` and
``from ... import`` of an exdex module inside exdex/, at module level or
inside a function (a lazy import is still a dependency), except those under
``if TYPE_CHECKING:`` (annotations only, never run). A package's
``__init__`` re-exporting its own submodules is not an edge.

* no import cycles between modules;
* no private name crossing modules: ``from exdex.x import _name`` of a name
  that is not a module, or ``module._name`` on an imported exdex module (a
  helper shared by modules lives in a private module of its own, e.g.
  exdex._validate, under a name without underscore);
* layers: the core modules (exdex.*) import no subpackage; exdex.design,
  exdex.engines and exdex.studies import no exdex.cli; exdex.design and
  exdex.engines import no exdex.studies (a study uses the library, not the
  other way round).

Each check is run on a small hand-made package first, so that it is known
to fail on a cycle, a private import and a back edge.
"""
import ast
import os
import pathlib

import pytest

from made_up_tree import write_tree

ROOT = pathlib.Path(__file__).resolve().parents[2]
PKG = ROOT / "exdex"

#: private names that cross modules today, each with its reason; a new one fails the test
KNOWN_PRIVATE = {
    # serialisation finds the motion classes as the subclasses of scene's private base class
    ("exdex.io", "exdex.scene", "_Motion"),
}


def modules(pkg):
    """{dotted name: path} of the .py files under pkg, plus extension modules (their .pyi)."""
    out = {}
    base = pkg.parent
    for path in pkg.rglob("*.py"):
        rel = path.relative_to(base).with_suffix("")
        parts = list(rel.parts)
        if parts[-1] == "__init__":
            parts = parts[:-1]
        out[".".join(parts)] = path
    for path in pkg.rglob("*.pyi"):
        name = ".".join(path.relative_to(base).with_suffix("").parts)
        out.setdefault(name, None)   # compiled: no source to read
    return out


def _type_checking(node):
    t = node.test
    return (isinstance(t, ast.Name) and t.id == "TYPE_CHECKING") or (
        isinstance(t, ast.Attribute) and t.attr == "TYPE_CHECKING")


def _walk(tree):
    """All nodes except those under ``if TYPE_CHECKING:``."""
    todo = [tree]
    while todo:
        node = todo.pop()
        yield node
        for child in ast.iter_child_nodes(node):
            if isinstance(child, ast.If) and _type_checking(child):
                todo.extend(child.orelse)
                continue
            todo.append(child)


def scan(pkg):
    """(edges {(a, b)}, private uses [(a, b, name)]) of the package at pkg."""
    mods = modules(pkg)
    top = pkg.name
    edges, private = set(), []
    for name, path in mods.items():
        if path is None:
            continue
        is_pkg = path.name == "__init__.py"
        here = name if is_pkg else name.rpartition(".")[0]
        tree = ast.parse(path.read_text(), str(path))
        aliases = {}   # local name -> exdex module it is bound to
        for node in _walk(tree):
            targets = []
            if isinstance(node, ast.Import):
                for a in node.names:
                    if a.name == top or a.name.startswith(top + "."):
                        targets.append(a.name)
                        if a.asname:
                            aliases[a.asname] = a.name
            elif isinstance(node, ast.ImportFrom):
                if node.level:
                    base = here.split(".")
                    base = base[:len(base) - node.level + 1]
                    mod = ".".join(base + ([node.module] if node.module else []))
                else:
                    mod = node.module or ""
                if not (mod == top or mod.startswith(top + ".")):
                    continue
                for a in node.names:
                    sub = f"{mod}.{a.name}"
                    if sub in mods:
                        targets.append(sub)
                        aliases[a.asname or a.name] = sub
                    else:
                        targets.append(mod)
                        if a.name.startswith("_") and not a.name.startswith("__"):
                            private.append((name, mod, a.name))
            for t in targets:
                while t not in mods and "." in t:
                    t = t.rpartition(".")[0]
                if t == name or (is_pkg and t.startswith(name + ".")):
                    continue   # a package re-exporting its own submodules
                edges.add((name, t))
        for node in _walk(tree):
            if isinstance(node, ast.Attribute) and isinstance(node.value, ast.Name) and node.value.id in aliases:
                if node.attr.startswith("_") and not node.attr.startswith("__"):
                    target = aliases[node.value.id]
                    if f"{target}.{node.attr}" not in mods and target != name:
                        private.append((name, target, node.attr))
    return edges, private


def cycles(edges):
    """Strongly connected components with more than one module (Tarjan)."""
    graph = {}
    for a, b in edges:
        graph.setdefault(a, set()).add(b)
        graph.setdefault(b, set())
    index, low, stack, on, out = {}, {}, [], set(), []

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
            comp = set()
            while True:
                w = stack.pop()
                on.discard(w)
                comp.add(w)
                if w == v:
                    break
            if len(comp) > 1:
                out.append(frozenset(comp))

    for v in sorted(graph):
        if v not in index:
            visit(v)
    return out


def layer(name, top="exdex"):
    """0 core, 1 design / engines, 2 studies, 3 cli (and ``python -m exdex``)."""
    if name == "exdex.__main__":
        return 3
    parts = name.split(".")
    sub = parts[1] if len(parts) > 2 or (len(parts) == 2 and parts[1] in ("design", "engines", "studies", "cli")) else ""
    return {"": 0, "design": 1, "engines": 1, "studies": 2, "cli": 3}.get(sub, 0)


def back_edges(edges, mods):
    """Edges to a higher layer (the top package's __init__ is above every layer)."""
    out = set()
    for a, b in edges:
        if b == "exdex" or a == "exdex":
            continue
        if layer(b) > layer(a) or (layer(a) == layer(b) == 1 and a.split(".")[1] != b.split(".")[1]):
            out.add((a, b))
    return out


# ---------------------------------------------------------------- the checks on a made-up package

def test_the_checks_fail_on_a_cycle_a_private_import_and_a_back_edge(tmp_path):
    pkg = tmp_path / "exdex"
    write_tree(pkg, {
        "__init__.py": "from exdex import a\nfrom exdex.design import plan\n",
        "a.py": "from exdex.b import helper\n",
        "b.py": "def helper():\n    from exdex import a\n    return a\n",           # lazy: still a cycle
        "c.py": "from typing import TYPE_CHECKING\nif TYPE_CHECKING:\n    from exdex import d\n",
        "d.py": "from exdex import c\nfrom exdex.a import _hidden\nimport exdex.b as B\nB._x\n",
        "design/__init__.py": "from exdex.design import plan\n",
        "design/plan.py": "from exdex.cli import main\n",                        # library -> command line
        # a method's lazy import of a study: a back edge as much as one at the top
        "design/fit.py": "class Fit:\n    def exact(self):\n        from exdex.studies import paper\n        return paper\n",
        # a method's lazy import closing a cycle: Model.stepper() of a stepper that imports the model
        "model.py": "class Model:\n    def stepper(self):\n        from exdex.stepper import Stepper\n        return Stepper(self)\n",
        "stepper.py": "from exdex.model import Model\n",
        "studies/__init__.py": "", "studies/paper.py": "import numpy\n",
        "cli/__init__.py": "", "cli/main.py": "import exdex\n",
    })
    edges, private = scan(pkg)
    assert set(cycles(edges)) == {frozenset({"exdex.a", "exdex.b"}),   # c <-> d only under TYPE_CHECKING
                                  frozenset({"exdex.model", "exdex.stepper"})}
    assert sorted(private) == [("exdex.d", "exdex.a", "_hidden"), ("exdex.d", "exdex.b", "_x")]
    assert back_edges(edges, modules(pkg)) == {("exdex.design.plan", "exdex.cli.main"),
                                               ("exdex.design.fit", "exdex.studies.paper")}
    # a package re-exporting its own submodules is no edge; a module importing the package is one
    assert ("exdex", "exdex.a") not in edges and ("exdex.design", "exdex.design.plan") not in edges
    assert ("exdex.cli.main", "exdex") in edges


# ---------------------------------------------------------------- the checks on exdex

@pytest.fixture(scope="module")
def graph():
    return scan(PKG)


def test_no_import_cycles(graph):
    found = set(cycles(graph[0]))
    assert not found, f"import cycles: {[sorted(c) for c in found]}"


def test_no_private_names_across_modules(graph):
    found = set(graph[1])
    assert found <= KNOWN_PRIVATE, (
        "private names used across modules (give the helper a home of its own, e.g. exdex._validate): "
        f"{sorted(found - KNOWN_PRIVATE)}")


def test_layers_have_no_back_edges(graph):
    found = back_edges(graph[0], modules(PKG))
    assert not found, f"imports from a higher layer: {sorted(found)}"


def test_every_module_is_read():
    """The scan sees every module of every subpackage (a folder without
    __init__.py would be left out of the wheel and of these checks)."""
    mods = modules(PKG)
    for sub in ("design", "studies", "engines", "cli"):
        assert f"exdex.{sub}" in mods
    for dirpath, _, files in os.walk(PKG):
        if "__pycache__" in dirpath:
            continue
        if any(f.endswith(".py") for f in files):
            assert "__init__.py" in files, f"{dirpath} holds modules but is not a package"
