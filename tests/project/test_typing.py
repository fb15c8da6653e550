"""Type hints of the public API, checked by mypy (the package ships py.typed).

* mypy on the package itself: zero errors;
* mypy on a typed user script (tests/project/typing/usage.py): zero errors, and the
  script runs;
* mypy on wrong calls (tests/project/typing/misuse.py): exactly the marked lines are
  reported, so the hints are live, not ``Any``;
* every public function and method of the API modules has annotations on all
  of its parameters and its return value (CLI plumbing excluded).
"""
import dataclasses
import importlib
import inspect
import os
import re
import subprocess
import sys

import pytest

import exdex

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
HERE = os.path.join(ROOT, "tests", "project", "typing")

pytest.importorskip("mypy", reason="mypy comes with the test extra: pip install -e .[test]")


def _mypy(target, cache):
    p = subprocess.run([sys.executable, "-m", "mypy", "--config-file", os.path.join(ROOT, "pyproject.toml"),
                        "--cache-dir", str(cache), "--no-error-summary", "--hide-error-context", target],
                       capture_output=True, text=True, cwd=ROOT)
    return p.returncode, [ln for ln in (p.stdout + p.stderr).splitlines() if ": error:" in ln]


@pytest.fixture(scope="module")
def cache(tmp_path_factory):
    """One mypy cache for the module's runs (the first one fills it)."""
    return tmp_path_factory.mktemp("mypy_cache")


def test_mypy_on_the_package(cache):
    rc, errors = _mypy("exdex", cache)
    assert errors == [] and rc == 0, "\n".join(errors)


def test_mypy_on_a_typed_user_script(cache):
    rc, errors = _mypy(os.path.join("tests", "project", "typing", "usage.py"), cache)
    assert errors == [] and rc == 0, "\n".join(errors)
    run = subprocess.run([sys.executable, os.path.join(HERE, "usage.py")], capture_output=True, text=True)
    assert run.returncode == 0, run.stderr[-2000:]


def test_mypy_rejects_wrong_calls(cache):
    path = os.path.join(HERE, "misuse.py")
    with open(path) as f:
        marked = {i for i, line in enumerate(f, 1) if "# E:" in line}
    rc, errors = _mypy(os.path.join("tests", "project", "typing", "misuse.py"), cache)
    reported = {int(re.match(r"[^:]+:(\d+):", e).group(1)) for e in errors}
    assert rc != 0
    assert reported == marked, f"expected errors on lines {sorted(marked)}, mypy reported:\n" + "\n".join(errors)


def _public_callables():
    modules = {m: m.__all__ for m in [exdex] + [importlib.import_module(f"exdex.{n}")
                                               for n in ("scene", "simulate", "batch", "paper", "tool", "plan",
                                                         "fit", "sequence")]}
    skip = {"add_arguments", "run"}  # command-line plumbing of `exdex paper` / `exdex tool`
    seen = {}
    for mod, names in modules.items():
        for name in names:
            obj = getattr(mod, name)
            if name in skip or inspect.ismodule(obj) or (isinstance(obj, type) and issubclass(obj, BaseException)):
                continue
            if inspect.isfunction(obj):
                seen[f"{mod.__name__}.{name}"] = obj
            elif inspect.isclass(obj):
                for attr, member in vars(obj).items():
                    if attr.startswith("_") and attr not in ("__init__", "__call__"):
                        continue
                    if isinstance(member, (classmethod, staticmethod)):
                        member = member.__func__
                    elif isinstance(member, property):
                        member = member.fget
                    if inspect.isfunction(member) and not (attr == "__init__" and dataclasses.is_dataclass(obj)):
                        seen[f"{mod.__name__}.{name}.{attr}"] = member
    return seen


def test_public_api_is_fully_annotated():
    funcs = _public_callables()
    assert len(funcs) > 60  # the API's size: a broken collector would pass vacuously
    missing = []
    for qual, fn in sorted(funcs.items()):
        sig = inspect.signature(fn)
        for p in sig.parameters.values():
            if p.name in ("self", "cls"):
                continue
            if p.annotation is inspect.Parameter.empty:
                missing.append(f"{qual}({p.name})")
        if sig.return_annotation is inspect.Signature.empty:
            missing.append(f"{qual} -> ?")
    assert not missing, "unannotated: " + ", ".join(missing)
