"""exdex.cli.run: ``exdex run SCENE``: the files it writes (the NPZ loads back
bit-identical to exdex.simulate of the scene), options overriding the scene
file's, errors as one-line messages, and a run without the plot extra."""
import os
import subprocess
import sys

import pytest

import exdex
from exdex import cli
from scenes import falling_box_scenes

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def _cli(*args, cwd):
    env = dict(os.environ, PYTHONPATH=ROOT, MPLBACKEND="Agg")
    return subprocess.run([sys.executable, "-m", "exdex", *args], capture_output=True, text=True, cwd=cwd,
                          env=env, timeout=300)


@pytest.mark.warns_by_design("impact", "outline")
def test_cli_run_writes_result_figure_and_animation(tmp_path):
    sc = falling_box_scenes()["planar"]
    exdex.save_scene(sc, tmp_path / "drop.json", simulate=dict(t_end=0.9, dt=2e-3))
    p = _cli("run", "drop.json", "--out", "o", "--animate", "--fps", "5", "--no-progress", cwd=tmp_path)
    assert p.returncode == 0, p.stderr
    out = tmp_path / "o"
    assert sorted(os.listdir(out)) == ["drop.csv", "drop.gif", "drop.npz", "drop.png"]
    back = exdex.Result.load(out / "drop.npz")
    want = exdex.simulate(sc, 0.9, 2e-3)
    assert back.q.tobytes() == want.q.tobytes() and back.dt == 2e-3
    assert "drop.gif" in p.stdout and "exdex.Result planar" in p.stdout
    # command-line options override the file's
    p = _cli("run", "drop.json", "--out", "o2", "--t-end", "0.5", "--dt", "0.01", "--method", "explicit",
             "--no-progress", cwd=tmp_path)
    assert p.returncode == 0, p.stderr
    back = exdex.Result.load(tmp_path / "o2" / "drop.npz")
    assert back.method == "explicit" and back.t[-1] == 0.5 and len(back.t) == 51


def test_cli_run_errors_are_messages(tmp_path):
    p = _cli("run", "missing.toml", cwd=tmp_path)
    assert p.returncode != 0 and "no such scene file: missing.toml" in p.stderr
    (tmp_path / "bad.toml").write_text("schema = 5\n")
    p = _cli("run", "bad.toml", cwd=tmp_path)
    assert p.returncode != 0 and "unsupported scene-file schema 5" in p.stderr and "Traceback" not in p.stderr
    sc = falling_box_scenes()["translation"]
    exdex.save_scene(sc, tmp_path / "s.toml")
    p = _cli("run", "s.toml", "--dt", "-1", "--no-progress", cwd=tmp_path)
    assert p.returncode != 0 and "dt must be" in p.stderr and "Traceback" not in p.stderr


def test_cli_run_without_matplotlib(tmp_path):
    """Without the plot extra, ``exdex run`` still writes the result (CSV, NPZ)
    and says the figure needs matplotlib; ``--animate`` stops before simulating
    with the one-line message naming the extra."""
    blocker = (
        "import importlib.abc, sys\n"
        "class _B(importlib.abc.MetaPathFinder):\n"
        "    def find_spec(self, name, path=None, target=None):\n"
        "        if name.split('.')[0] in ('matplotlib', 'tqdm'):\n"
        "            raise ModuleNotFoundError(f'No module named {name!r}', name=name)\n"
        "sys.meta_path.insert(0, _B())\n"
        "from exdex.cli import main\n"
        "sys.exit(main(sys.argv[1:]))\n")
    exdex.save_scene(falling_box_scenes()["translation"], tmp_path / "s.toml", simulate=dict(t_end=0.5, dt=1e-2))
    env = dict(os.environ, PYTHONPATH=ROOT)
    p = subprocess.run([sys.executable, "-c", blocker, "run", "s.toml", "--out", "o"], capture_output=True,
                       text=True, cwd=tmp_path, env=env, timeout=300)
    assert p.returncode == 0, p.stderr
    assert sorted(os.listdir(tmp_path / "o")) == ["s.csv", "s.npz"]
    assert "needs matplotlib" in p.stdout and "exdex[plot]" in p.stdout
    p = subprocess.run([sys.executable, "-c", blocker, "run", "s.toml", "--out", "o2", "--animate"],
                       capture_output=True, text=True, cwd=tmp_path, env=env, timeout=300)
    assert p.returncode == 3 and "exdex[plot]" in p.stderr and len(p.stderr.strip().splitlines()) == 1, p.stderr
    assert not (tmp_path / "o2").exists()
