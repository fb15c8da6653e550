"""The API reference builds from the docstrings without a warning.

``python docs/build_api.py OUT`` (pdoc) must write a page per public module,
raise no warning (an unparsable docstring or a broken link is a warning) and
render no raw reStructuredText roles (``:func:`...```) in the docstrings.
"""
import pathlib
import re
import subprocess
import sys

import pytest

pytest.importorskip("pdoc")

ROOT = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "docs"))
import build_api  # noqa: E402


def test_api_reference_builds_without_warnings(tmp_path):
    p = subprocess.run([sys.executable, str(ROOT / "docs" / "build_api.py"), str(tmp_path)],
                       capture_output=True, text=True, timeout=300, cwd=str(ROOT))
    assert p.returncode == 0, p.stderr
    assert "(0 warnings)" in p.stdout and "warning" not in p.stderr
    pages = {m: tmp_path / (m.replace(".", "/") + ".html") for m in build_api.MODULES}
    missing = [m for m, f in pages.items() if not f.is_file()]
    assert not missing, missing
    io_page = pages["exdex.io"].read_text()
    assert "save_scene" in io_page and "load_scene" in io_page
    raw = []
    for f in pages.values():
        for doc in re.findall(r'<div class="docstring">(.*?)</div>', f.read_text(), re.S):
            raw += re.findall(r":(?:func|meth|class|mod|data|attr):`[^`]*`", doc)
    assert not raw, raw[:5]
