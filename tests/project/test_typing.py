"""Type hints of the public API, checked by mypy (the package ships py.typed).

* mypy on the package itself: zero errors;
* mypy on a typed user script (tests/project/typing/usage.py): zero errors, and the
  script runs;
* mypy on a user's snippet outside the repository (its own folder, no config, no
  PYTHONPATH): it finds the installed package (.ci/setup.sh's editable install
  included) and its types, so a wrong assignment is reported and nothing else;
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


SNIPPET = """\
import exdex

scene = exdex.Scene(body=exdex.Body(mass=0.1), grasp=exdex.Grasp(mu=0.5, grip_force=1.0))
res: exdex.Result = exdex.simulate(scene, 0.1, 1e-3)
q = exdex.quaternion_from_matrix(scene.gripper_rotation)
wrong: str = res.t  # the one error
"""


def test_mypy_sees_the_installed_package_from_a_user_folder(tmp_path):
    """The install as a user has it (not the repository on the path): a snippet in its own folder."""
    import importlib.metadata

    try:
        importlib.metadata.distribution("exdex")
    except importlib.metadata.PackageNotFoundError:
        pytest.skip("exdex is not installed (a source checkout on PYTHONPATH): nothing to find")
    (tmp_path / "snippet.py").write_text(SNIPPET)
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "MYPYPATH")}
    p = subprocess.run([sys.executable, "-m", "mypy", "--no-incremental", "--no-error-summary", "snippet.py"],
                       capture_output=True, text=True, cwd=str(tmp_path), env=env)
    errors = [ln for ln in (p.stdout + p.stderr).splitlines() if ": error:" in ln]
    assert len(errors) == 1 and errors[0].startswith("snippet.py:6:") and "[assignment]" in errors[0], \
        "\n".join(errors)


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
                                               for n in ("scene", "simulate", "batch", "studies.paper", "design.tool",
                                                         "design.plan", "design.fit", "design.sequence")]}
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
