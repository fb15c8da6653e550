"""Execute every notebook in notebooks/ headless, so that none can rot.

Each notebook runs in a fresh python3 kernel (the environment running the
tests: jupyter_client replaces the kernelspec's "python" by sys.executable)
with notebooks/ as the working folder, the repository on PYTHONPATH (so a
source checkout works without installing) and matplotlib's Agg backend. A
cell that raises fails the test with the cell's traceback.
"""
import json
import os
import pathlib
import re

import pytest

nbformat = pytest.importorskip("nbformat")
nbclient = pytest.importorskip("nbclient")
pytest.importorskip("ipykernel")

ROOT = pathlib.Path(__file__).resolve().parents[2]
NOTEBOOKS = sorted((ROOT / "notebooks").glob("*.ipynb"))


#: ``exdex.<...>._name`` (attribute or ``from exdex.x import _name``), not dunders
PRIVATE = re.compile(r"\bexdex(?:\.[A-Za-z]\w*)*\._(?!_)\w+|\bfrom\s+exdex(?:\.\w+)*\s+import\s+[^\n#]*\b_(?!_)\w+")


def private_names(code):
    """The private exdex names a piece of code uses."""
    return PRIVATE.findall(code)


def test_the_private_name_check_sees_private_use():
    assert private_names("q = exdex.scene._quat_from_matrix(R)") == ["exdex.scene._quat_from_matrix"]
    assert private_names("from exdex.scene import Body, _unit") != []
    assert private_names("exdex._core.simulate(s)") == ["exdex._core"]
    assert private_names("exdex.quaternion_from_matrix(R); r.__class__; exdex.__version__") == []


@pytest.mark.parametrize("path", NOTEBOOKS, ids=[p.stem for p in NOTEBOOKS])
def test_notebook_uses_no_private_names(path):
    """Notebooks are for users: only the public API (no ``exdex.x._y``)."""
    cells = json.loads(path.read_text())["cells"]
    found = [n for c in cells if c["cell_type"] == "code" for n in private_names("".join(c["source"]))]
    assert not found, found


def test_notebooks_found():
    assert NOTEBOOKS, "no notebooks in notebooks/"


@pytest.mark.parametrize("path", NOTEBOOKS, ids=[p.stem for p in NOTEBOOKS])
def test_notebook_executes(path, monkeypatch):
    monkeypatch.setenv("PYTHONPATH", os.pathsep.join(filter(None, [str(ROOT), os.environ.get("PYTHONPATH")])))
    monkeypatch.setenv("MPLBACKEND", "Agg")
    nb = nbformat.read(str(path), as_version=4)
    client = nbclient.NotebookClient(nb, timeout=300, kernel_name="python3",
                                     resources={"metadata": {"path": str(path.parent)}})
    client.execute()
    errors = [o for c in nb.cells if c.cell_type == "code" for o in c.get("outputs", [])
              if o.get("output_type") == "error"]
    assert not errors
