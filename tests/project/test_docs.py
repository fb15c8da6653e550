"""The documentation site builds with one command, from the docstrings and the executed notebooks.

``python docs/build.py OUT --notebooks tutorial_2_robot_log`` (the API reference with pdoc, one
notebook executed and converted with nbconvert: the full build of all notebooks is the command
without ``--notebooks``; tests/project/test_notebooks.py executes every notebook already) must

* write the index, a page per public module (docs/build_api.py: no pdoc warning, an unparsable
  docstring or a broken reference is one; no raw reStructuredText roles ``:func:`...``` left), and the
  notebook's page with its executed outputs: the printed shape of a 1.2 s log at 125 Hz, 1.2 x 125 + 1
  = 151 samples (counted by hand), and its figure as an embedded PNG;
* fail on a relative link to a missing page and on a notebook cell that raises.
"""
import pathlib
import re
import subprocess
import sys

import pytest

pytest.importorskip("pdoc")
pytest.importorskip("nbconvert")
pytest.importorskip("nbclient")
pytest.importorskip("ipykernel")

ROOT = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "docs"))
import build  # noqa: E402
import build_api  # noqa: E402


@pytest.fixture(scope="module")
def site(tmp_path_factory):
    out = tmp_path_factory.mktemp("site")
    p = subprocess.run([sys.executable, str(ROOT / "docs" / "build.py"), str(out), "--notebooks",
                        "tutorial_2_robot_log"], capture_output=True, text=True, timeout=600, cwd=str(ROOT))
    return out, p


def test_site_builds_without_problems(site):
    out, p = site
    assert p.returncode == 0, p.stderr[-3000:]
    assert "(0 problems)" in p.stdout and "error:" not in p.stderr
    index = (out / "index.html").read_text()
    assert 'href="api/index.html"' in index and 'href="notebooks/tutorial_2_robot_log.html"' in index
    assert "Tutorial 2: replaying a robot log" in index   # the notebook's own heading


def test_api_reference_pages(site):
    out, p = site
    assert p.returncode == 0, p.stderr[-3000:]
    assert "API reference:" not in p.stderr          # a pdoc warning is a problem of the build
    pages = {m: out / "api" / (m.replace(".", "/") + ".html") for m in build_api.MODULES}
    missing = [m for m, f in pages.items() if not f.is_file()]
    assert not missing, missing
    io_page = pages["exdex.io"].read_text()
    assert "save_scene" in io_page and "load_scene" in io_page
    assert "quaternion_from_matrix" in pages["exdex.scene"].read_text()
    raw = []
    for f in pages.values():
        for doc in re.findall(r'<div class="docstring">(.*?)</div>', f.read_text(), re.S):
            raw += re.findall(r":(?:func|meth|class|mod|data|attr):`[^`]*`", doc)
    assert not raw, raw[:5]


def test_notebook_page_has_the_executed_outputs(site):
    out, p = site
    assert p.returncode == 0, p.stderr[-3000:]
    page = (out / "notebooks" / "tutorial_2_robot_log.html").read_text()
    assert "(151, 3, 3) (151, 3)" in page          # kin["R"].shape, kin["p"].shape of the 125 Hz log
    assert "final slide: exact" in page            # a printed result of a later cell
    assert page.count("data:image/png;base64,") >= 1
    assert build.broken_links(out) == []


def test_a_missing_page_is_a_broken_link(tmp_path):
    (tmp_path / "a").mkdir()
    (tmp_path / "index.html").write_text('<a href="a/page.html">p</a> <a href="https://example.org/x">x</a>'
                                         ' <a href="#top">t</a> <img src="data:image/png;base64,AA">')
    (tmp_path / "a" / "page.html").write_text('<a href="../index.html#s">back</a> <a href="missing.html">m</a>'
                                              ' <a href="../../outside.html">o</a>')
    assert build.broken_links(tmp_path) == [("a/page.html", "missing.html"), ("a/page.html", "../../outside.html")]


def test_build_fails_on_a_broken_link_and_a_raising_cell(tmp_path, monkeypatch):
    import nbformat

    books = tmp_path / "notebooks"
    books.mkdir()
    v4 = nbformat.v4
    nbformat.write(v4.new_notebook(cells=[v4.new_markdown_cell("# Good\n\nsee [the other](bad.ipynb) and "
                                                               "[a page that is not there](gone.ipynb)"),
                                          v4.new_code_cell("print(6 * 7)")]), str(books / "good.ipynb"))
    nbformat.write(v4.new_notebook(cells=[v4.new_code_cell("1 / 0")]), str(books / "bad.ipynb"))
    monkeypatch.setattr(build, "NOTEBOOKS", books)
    problems = build.build(tmp_path / "site", api=False)
    assert any(p.startswith("bad.ipynb: a cell raised") and "ZeroDivisionError" in p for p in problems), problems
    # bad.ipynb has no page (its cell raised), gone.ipynb is no notebook: both links are broken
    assert sum("broken link" in p for p in problems) == 2, problems
    good = (tmp_path / "site" / "notebooks" / "good.html").read_text()
    assert "42" in good and 'href="bad.html"' in good
    assert build.main([str(tmp_path / "site2"), "--no-api"]) == 1


def test_setup_installs_what_the_docs_and_the_api_need():
    """.ci/setup.sh installs the extras whose packages the docs (nbconvert, pdoc), the SciPy features
    and the explorer import; pyproject.toml's extras hold them."""
    tomllib = pytest.importorskip("tomllib")
    setup = (ROOT / ".ci" / "setup.sh").read_text()
    m = re.search(r'pip install -q -e "\.\[([a-z,]+)\]"', setup)
    assert m, "setup.sh's editable install line"
    installed = set(m.group(1).split(","))
    extras = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]["optional-dependencies"]
    need = {"docs": ("nbconvert", "pdoc", "nbclient", "ipykernel"), "design": ("scipy",), "explore": ("ipywidgets",),
            "plot": ("matplotlib",)}
    for extra, packages in need.items():
        assert extra in installed, extra
        names = {re.split(r"[<>=\[ ]", req)[0] for req in extras[extra]}
        assert set(packages) <= names, (extra, names)
