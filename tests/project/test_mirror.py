"""Tests mirror the code: every module has a test file named after it, in the
folder that mirrors its package.

The rule (Python): a module ``exdex/<path>/<m>.py`` -- every ``.py`` file
under exdex/ except ``__init__.py`` and ``__main__.py`` -- has its tests in
``tests/<path>/test_<m>.py``, with at least one ``def test_``. A private
module's leading underscore is dropped: ``exdex/_table.py`` is tested in
``tests/test_table.py``, ``exdex/engines/_runner.py`` in
``tests/engines/test_runner.py``. So a folder must not hold both ``m.py``
and ``_m.py`` (they would share one test file): that is a failure too. The
compiled extension modules (exdex._core, exdex._tool, written in C) are not
``.py`` files and are not covered here; the C side is:

The rule (C): every file ``csrc/<f>.c`` of the core has ``csrc/tests/test_<f>.c``
with at least one ``EXDEX_TEST(``.

Tests spanning modules live in tests/scenarios/ (and csrc/tests/scenarios/),
the repository's own checks in tests/project/; a test file that mirrors no
module is not a failure of this check.

Both checks are run on a small made-up tree first, so that each is known to
fail on a module without its test file.
"""
import pathlib
import re

from made_up_tree import write_tree

ROOT = pathlib.Path(__file__).resolve().parents[2]
PY_TEST = re.compile(r"^def test_\w*\(", re.M)
C_TEST = re.compile(r"\bEXDEX_TEST\(")


def mirror(rel):
    """The test file (relative path) of the module ``rel`` (a path under exdex/)."""
    rel = pathlib.PurePosixPath(rel)
    return (pathlib.PurePosixPath("tests") / rel.parent / f"test_{rel.stem.lstrip('_')}.py").as_posix()


def python_modules(root):
    """Paths (relative to exdex/, posix) of the modules the rule covers."""
    pkg = root / "exdex"
    return sorted(p.relative_to(pkg).as_posix() for p in pkg.rglob("*.py")
                  if p.name not in ("__init__.py", "__main__.py"))


def c_files(root):
    """Names of the core's C files (csrc/*.c)."""
    return sorted(p.name for p in (root / "csrc").glob("*.c"))


def problems(root):
    """What breaks the rules in the tree at root: a list of messages."""
    bad = []
    claimed = {}
    for rel in python_modules(root):
        test = mirror(rel)
        if test in claimed:
            bad.append(f"exdex/{rel} and exdex/{claimed[test]} would share the test file {test}: rename one")
            continue
        claimed[test] = rel
        path = root / test
        if not path.is_file():
            bad.append(f"exdex/{rel} has no test file {test}")
        elif not PY_TEST.search(path.read_text()):
            bad.append(f"{test} (the tests of exdex/{rel}) defines no test")
    for name in c_files(root):
        test = f"csrc/tests/test_{name}"
        path = root / test
        if not path.is_file():
            bad.append(f"csrc/{name} has no test file {test}")
        elif not C_TEST.search(path.read_text()):
            bad.append(f"{test} (the tests of csrc/{name}) defines no EXDEX_TEST")
    return bad


def listing(root):
    """(module, test file) pairs of the Python and the C side, for the eye."""
    return ([(f"exdex/{rel}", mirror(rel)) for rel in python_modules(root)]
            + [(f"csrc/{name}", f"csrc/tests/test_{name}") for name in c_files(root)])


def test_mirror_maps_private_modules_and_subpackages():
    assert mirror("scene.py") == "tests/test_scene.py"
    assert mirror("_table.py") == "tests/test_table.py"
    assert mirror("engines/_runner.py") == "tests/engines/test_runner.py"
    assert mirror("design/plan.py") == "tests/design/test_plan.py"


def test_the_check_fails_on_a_module_without_its_test_file(tmp_path):
    test = "def test_it():\n    pass\n"
    write_tree(tmp_path, {
        "exdex/__init__.py": "", "exdex/__main__.py": "", "exdex/sub/__init__.py": "",
        "exdex/a.py": "", "exdex/_b.py": "", "exdex/sub/c.py": "", "exdex/sub/_d.py": "",
        "tests/test_a.py": test, "tests/test_b.py": test, "tests/sub/test_c.py": test, "tests/sub/test_d.py": test,
        "csrc/core.c": "", "csrc/tests/test_core.c": "EXDEX_TEST(core_one)\n{\n}\n",
    })
    assert problems(tmp_path) == []
    assert ("exdex/sub/_d.py", "tests/sub/test_d.py") in listing(tmp_path)
    # a module without its file; one whose file sits in the wrong folder; one whose file has no test
    write_tree(tmp_path, {"exdex/sub/e.py": "", "exdex/f.py": "", "tests/sub/test_f.py": test,
                          "exdex/sub/g.py": "", "tests/sub/test_g.py": "def helper():\n    pass\n"})
    # a C file without its test file, and one whose test file registers no test
    write_tree(tmp_path, {"csrc/more.c": "", "csrc/empty.c": "", "csrc/tests/test_empty.c": "/* nothing */\n"})
    # a private module beside the public one of its name
    write_tree(tmp_path, {"exdex/_a.py": ""})
    assert problems(tmp_path) == [
        "exdex/a.py and exdex/_a.py would share the test file tests/test_a.py: rename one",
        "exdex/f.py has no test file tests/test_f.py",
        "exdex/sub/e.py has no test file tests/sub/test_e.py",
        "tests/sub/test_g.py (the tests of exdex/sub/g.py) defines no test",
        "csrc/tests/test_empty.c (the tests of csrc/empty.c) defines no EXDEX_TEST",
        "csrc/more.c has no test file csrc/tests/test_more.c",
    ]


def test_every_module_and_c_file_has_its_test_file():
    assert len(python_modules(ROOT)) > 30 and len(c_files(ROOT)) > 20      # the rule sees the package and csrc
    bad = problems(ROOT)
    assert not bad, "\n".join(bad)
