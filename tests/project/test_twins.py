"""Twin tests: one subject tested in the C suite and through the Python API.

A twin pointer is a line ``twin: <path>`` (a whole file: in its header
comment or module docstring) or ``twin: <path>::<name>`` (one test: in a
comment above it, before its decorators; the test it belongs to is the first
``EXDEX_TEST(name)`` or ``def name`` after it), path from the repository's
root. The checks:

* every pointer resolves: the file exists, and the named test is defined in it;
* pointers go both ways: the file (or test) pointed at points back;
* every scenario file of the C suite whose name a Python scenario file has
  (csrc/tests/scenarios/test_X.c and tests/scenarios/test_X.py) points at it.

The checks are run on a small made-up tree first, so that each is known to fail.
"""
import pathlib
import re

from made_up_tree import write_tree

ROOT = pathlib.Path(__file__).resolve().parents[2]
POINTER = re.compile(r"\btwin: ([\w./-]+\.(?:c|py))(?:::(\w+))?")
C_TEST = re.compile(r"EXDEX_TEST\((\w+)\)")
PY_TEST = re.compile(r"^def (\w+)\(", re.M)


def _tests(path):
    """{test name: offset of its definition} of a C or Python test file."""
    text = path.read_text()
    pattern = C_TEST if path.suffix == ".c" else PY_TEST
    return {m.group(1): m.start() for m in pattern.finditer(text)}


def pointers(root):
    """[(source file, source test or None, target file, target test or None)]
    of every twin pointer in root's csrc/tests and tests folders."""
    out = []
    files = sorted((root / "csrc" / "tests").rglob("*.c")) + sorted((root / "tests").rglob("*.py"))
    for path in files:
        if path.resolve() == pathlib.Path(__file__).resolve():
            continue
        text = path.read_text()
        defs = sorted((off, name) for name, off in _tests(path).items())
        for m in POINTER.finditer(text):
            src = path.relative_to(root).as_posix()
            if m.group(2) is None:
                out.append((src, None, m.group(1), None))
                continue
            after = [name for off, name in defs if off > m.end()]
            out.append((src, after[0] if after else "<no test after the pointer>", m.group(1), m.group(2)))
    return out


def problems(root):
    """Every broken, one-way or missing twin pointer under root, as sentences."""
    found = pointers(root)
    have = set(found)
    bad = []
    for src, stest, dst, dtest in found:
        where = src + (f"::{stest}" if stest else "")
        target = root / dst
        if not target.is_file():
            bad.append(f"{where}: twin {dst} does not exist")
            continue
        if dtest is not None and dtest not in _tests(target):
            bad.append(f"{where}: twin {dst}::{dtest} is no test of that file")
            continue
        if (dst, dtest, src, stest) not in have:
            back = src + (f"::{stest}" if stest else "")
            bad.append(f"{where}: twin {dst}{'::' + dtest if dtest else ''} does not point back at {back}")
    for c in sorted((root / "csrc" / "tests" / "scenarios").glob("test_*.c")):
        py = root / "tests" / "scenarios" / (c.stem + ".py")
        if py.is_file():
            pair = (c.relative_to(root).as_posix(), None, py.relative_to(root).as_posix(), None)
            if pair not in have:
                bad.append(f"{pair[0]} and {pair[2]} test one subject under one name but {pair[0]} "
                           f"has no line 'twin: {pair[2]}'")
    return bad


def test_the_checks_fail_on_a_broken_a_one_way_and_a_missing_pointer(tmp_path):
    write_tree(tmp_path, {
        # a good pair, file and test
        "csrc/tests/scenarios/test_a.c": "/* twin: tests/scenarios/test_a.py */\n"
                                         "/* twin: tests/scenarios/test_a.py::test_drop */\nEXDEX_TEST(a_drop)\n{\n}\n",
        "tests/scenarios/test_a.py": '"""twin: csrc/tests/scenarios/test_a.c"""\n\n\n'
                                     "# twin: csrc/tests/scenarios/test_a.c::a_drop\n@mark\ndef test_drop():\n    pass\n",
        # same name, no pointer
        "csrc/tests/scenarios/test_b.c": "EXDEX_TEST(b_one)\n{\n}\n",
        "tests/scenarios/test_b.py": "def test_one():\n    pass\n",
        # a pointer at a missing test, one at a missing file, one that is not returned
        "csrc/tests/test_c.c": "/* twin: tests/test_c.py::test_gone */\nEXDEX_TEST(c_x)\n{\n}\n"
                               "/* twin: tests/test_nowhere.py */\n",
        "tests/test_c.py": '"""twin: csrc/tests/scenarios/test_a.c"""\n',
    })
    assert ("csrc/tests/scenarios/test_a.c", "a_drop", "tests/scenarios/test_a.py", "test_drop") in pointers(tmp_path)
    assert ("tests/scenarios/test_a.py", "test_drop", "csrc/tests/scenarios/test_a.c", "a_drop") in pointers(tmp_path)
    bad = problems(tmp_path)
    assert len(bad) == 4, bad
    assert any("test_c.py::test_gone is no test" in b for b in bad)
    assert any("test_nowhere.py does not exist" in b for b in bad)
    assert any(b.startswith("tests/test_c.py: twin csrc/tests/scenarios/test_a.c does not point back") for b in bad)
    assert any("test_b.c has no line 'twin: tests/scenarios/test_b.py'" in b for b in bad)
    assert not any("test_a.py::test_drop" in b or "test_a.c::a_drop" in b for b in bad)


def test_every_twin_pointer_resolves_and_points_back():
    assert pointers(ROOT), "no twin pointers found"
    bad = problems(ROOT)
    assert not bad, "\n".join(bad)
