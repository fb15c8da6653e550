"""Module paths that moved into subpackages (exdex._moved): the old path
imports the very module at the new path, with a DeprecationWarning naming
it; the public names of exdex (exdex.plan, exdex.tool, ...) stay without one.
All cases run in one fresh interpreter (no earlier import of the test
session hides a warning), attributes first, each old path imported once."""
import json
import subprocess
import sys
import textwrap

import pytest

from exdex import _moved

CHILD = textwrap.dedent("""
    import importlib, json, sys, warnings
    import exdex
    out = []
    for old, new, how in json.loads(sys.argv[1]):
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            if how == "import":
                exec(f"import {old}")   # an import statement, as users write it
                mod = sys.modules[old]
            else:
                mod = getattr(exdex, old.split(".", 1)[1])
        real = importlib.import_module(new)
        dep = [w for w in caught if issubclass(w.category, DeprecationWarning)]
        out.append(dict(old=old, how=how, same=mod is real, spec=real.__spec__.name,
                        dep=[str(w.message) for w in dep], where=[w.filename for w in dep],
                        in_modules=sys.modules.get(old) is real))
    print(json.dumps(out))
""")

PUBLIC = ["plan", "sequence", "tool", "paper"]
OTHER = ["fit", "bench", "hold", "cli_run"]


@pytest.fixture(scope="module")
def cases():
    todo = [(f"exdex.{n}", _moved.MOVED[f"exdex.{n}"], "attribute") for n in PUBLIC + OTHER]
    todo += [(old, new, "import") for old, new in sorted(_moved.MOVED.items())]
    p = subprocess.run([sys.executable, "-c", CHILD, json.dumps(todo)], capture_output=True, text=True, timeout=300)
    assert p.returncode == 0, p.stderr[-3000:]
    return {(c["old"], c["how"]): c for c in json.loads(p.stdout.strip().splitlines()[-1])}


@pytest.mark.parametrize("old", sorted(_moved.MOVED))
def test_an_old_path_imports_the_moved_module_with_a_warning(cases, old):
    out, new = cases[old, "import"], _moved.MOVED[old]
    assert out["same"] and out["in_modules"] and out["spec"] == new   # one module, its own spec kept
    assert len(out["dep"]) == 1 and new in out["dep"][0] and old in out["dep"][0]
    assert out["where"] == ["<string>"]   # the warning points at the import statement, not at importlib


@pytest.mark.parametrize("name", PUBLIC)
def test_public_attributes_of_exdex_are_the_moved_modules_without_a_warning(cases, name):
    out = cases[f"exdex.{name}", "attribute"]
    assert out["same"] and out["dep"] == []


@pytest.mark.parametrize("name", OTHER)
def test_other_old_attributes_warn(cases, name):
    out = cases[f"exdex.{name}", "attribute"]
    assert out["same"] and len(out["dep"]) == 1 and _moved.MOVED[f"exdex.{name}"] in out["dep"][0]


def test_unknown_attribute_is_an_attribute_error():
    import exdex

    with pytest.raises(AttributeError, match="no attribute 'no_such_module'"):
        exdex.no_such_module  # noqa: B018


def test_every_new_path_exists():
    import importlib.util

    for new in _moved.MOVED.values():
        assert importlib.util.find_spec(new) is not None, new
