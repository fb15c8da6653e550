"""The package as a user gets it: sdist -> wheel -> a fresh virtual environment.

One build per test session (module fixture, ~15-30 s): ``python -m build``
writes the sdist from the source tree and then builds the wheel from that
sdist alone (unpacked in a temporary folder), so a file missing from the sdist
breaks the wheel build. Build isolation is off to keep the run offline and
fast: the build requirements (setuptools >= 77, numpy) come from the test
environment, which the ``test`` extra provides.

The wheel must carry GSL: its extensions may not need libgsl at run time
(``ldd``), ``auditwheel`` must find no external library to graft, and the
wheel must import and simulate in a fresh venv, also with libgsl made
unloadable (a private mount namespace that hides the library files).
"""
import glob
import os
import re
import shutil
import subprocess
import sys
import tarfile
import venv
import zipfile

import pytest

pytestmark = pytest.mark.packaging

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
PY = sys.executable

# a scene that needs GSL at run time: the event method integrates with GSL's rk8pd
SMOKE = r"""
import sys, exdex
print("FILE", exdex.__file__)
res = exdex.simulate(exdex.paper.fig3_scene(), 1.5, 0.01, method="event")
print("FINAL", repr(float(res.displacement[-1, 0])))
from exdex import tool as T
print("VOL", repr(T.cone_volume(T.tool_rows(T.ToolProblem(phi=[0.3], box=T.Box.eq13()), T.Tool(theta=2.0), 0.3))))
"""


def _run(cmd, **kw):
    p = subprocess.run(cmd, capture_output=True, text=True, **kw)
    assert p.returncode == 0, f"{cmd} failed ({p.returncode}):\n{p.stdout[-3000:]}\n{p.stderr[-3000:]}"
    return p.stdout


def _tracked(*folders):
    """Files git tracks under the given folders (None outside a git checkout)."""
    if shutil.which("git") is None or not os.path.isdir(os.path.join(ROOT, ".git")) and not os.path.isfile(
            os.path.join(ROOT, ".git")):
        return None
    p = subprocess.run(["git", "-C", ROOT, "ls-files", *folders], capture_output=True, text=True)
    return [f for f in p.stdout.split() if os.path.exists(os.path.join(ROOT, f))] if p.returncode == 0 else None


@pytest.fixture(scope="module")
def dist(tmp_path_factory):
    out = tmp_path_factory.mktemp("dist")
    env = dict(os.environ, EXDEX_GSL_LINK="auto")
    p = subprocess.run([PY, "-m", "build", "--no-isolation", "--outdir", str(out), ROOT], env=env, cwd=ROOT,
                       capture_output=True, text=True)
    log = p.stdout + p.stderr
    assert p.returncode == 0, f"python -m build failed:\n{log[-4000:]}"
    sdists = glob.glob(str(out / "exdex-*.tar.gz"))
    wheels = glob.glob(str(out / "exdex-*.whl"))
    assert len(sdists) == 1 and len(wheels) == 1, log[-2000:]
    # python -m build builds the wheel from the unpacked sdist, not from the tree
    assert "Building wheel from sdist" in log, log[-2000:]
    return {"sdist": sdists[0], "wheel": wheels[0], "out": out}


def test_sdist_has_everything_a_build_needs(dist):
    with tarfile.open(dist["sdist"]) as tf:
        names = {n.split("/", 1)[1] for n in tf.getnames() if "/" in n}
    print("sdist:", os.path.basename(dist["sdist"]), len(names), "entries")
    must = ["LICENSE", "README.md", "pyproject.toml", "setup.py", "MANIFEST.in", "exdex/py.typed",
            "csrc/exdex.h", "csrc/Makefile",
            "exdex/_coremodule.c", "exdex/_toolmodule.c", "exdex/_gslstatic.c", "tests/data/reference.dat"]
    tracked = _tracked("csrc", "exdex", "tests")
    if tracked is not None:
        must += tracked
    missing = sorted(set(must) - names)
    assert not missing, f"missing from the sdist: {missing}"
    built = sorted(n for n in names if n.endswith((".o", ".so", ".a", ".pyc")))
    assert not built, f"build products in the sdist: {built}"


def test_wheel_metadata_and_contents(dist):
    with zipfile.ZipFile(dist["wheel"]) as z:
        names = set(z.namelist())
        meta = z.read(next(n for n in names if n.endswith(".dist-info/METADATA"))).decode()
    print("wheel:", os.path.basename(dist["wheel"]))
    assert "exdex/py.typed" in names
    assert any(n.endswith(".dist-info/licenses/LICENSE") for n in names)
    assert sum(1 for n in names if re.match(r"exdex/_(core|tool)\..*\.so$", n)) == 2
    assert not [n for n in names if n.endswith(".c")], "C sources belong in the sdist, not the wheel"
    tracked = _tracked("exdex")
    if tracked is not None:   # every module of every subpackage (exdex.design, .studies, .engines, .cli)
        missing = sorted(n for n in tracked if n.endswith((".py", ".pyi", "py.typed")) and n not in names)
        assert not missing, f"modules missing from the wheel: {missing}"
    assert "License-Expression: MIT" in meta
    assert "Requires-Python: >=3.10" in meta
    assert "Classifier: Typing :: Typed" in meta
    with open(os.path.join(ROOT, "LICENSE")) as f:
        lic = f.read()
    assert lic.startswith("MIT License") and "Copyright (c) 2026 the exdex developers" in lic


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="ldd and auditwheel are Linux tools")
def test_wheel_extensions_carry_gsl(dist, tmp_path):
    with zipfile.ZipFile(dist["wheel"]) as z:
        z.extractall(tmp_path)
    sos = glob.glob(str(tmp_path / "exdex" / "*.so"))
    assert len(sos) == 2
    for so in sos:
        deps = _run(["ldd", so])
        print(os.path.basename(so), "ldd:\n" + deps)
        assert "libgsl" not in deps, f"{so} still needs libgsl at run time"
        if shutil.which("nm"):
            exported = _run(["nm", "-D", "--defined-only", so])
            gsl_syms = [ln for ln in exported.splitlines() if re.search(r"\b(gsl|cblas)_", ln)]
            assert not gsl_syms, f"GSL symbols exported from {so}: {gsl_syms[:5]}"
    aw = shutil.which("auditwheel", path=os.path.dirname(PY) + os.pathsep + os.environ.get("PATH", ""))
    assert aw, "auditwheel is missing: install the test extra (pip install -e .[test])"
    show = subprocess.run([aw, "show", dist["wheel"]], capture_output=True, text=True)
    text = show.stdout + show.stderr
    print(text)
    assert show.returncode == 0, text
    assert re.search(r'platform tag:\s*"manylinux_\d+_\d+_\w+"', text), text
    assert "libgsl" not in text
    # repair retags the wheel (nothing to graft): a manylinux wheel a user can install
    env = dict(os.environ, PATH=os.path.dirname(PY) + os.pathsep + os.environ.get("PATH", ""))
    rep = subprocess.run([aw, "repair", "-w", str(tmp_path / "repaired"), dist["wheel"]],
                         capture_output=True, text=True, env=env)
    assert rep.returncode == 0, rep.stdout + rep.stderr
    fixed = glob.glob(str(tmp_path / "repaired" / "*.whl"))
    print("repaired:", [os.path.basename(w) for w in fixed])
    assert len(fixed) == 1 and re.search(r"-manylinux_\d+_\d+_x86_64\.whl$|-manylinux_\d+_\d+_aarch64\.whl$",
                                         fixed[0])


@pytest.fixture(scope="module")
def fresh_venv(dist, tmp_path_factory):
    """A new venv holding only the wheel; its dependencies (numpy, matplotlib,
    tqdm) come from the test environment's site-packages through a .pth file
    placed after the venv's own site-packages, as --system-site-packages does."""
    root = tmp_path_factory.mktemp("venv") / "fresh"
    venv.EnvBuilder(with_pip=False, clear=True).create(root)
    py = str(root / "bin" / "python")
    _run([PY, "-m", "pip", "--python", py, "install", "--no-deps", "--no-index", "--no-cache-dir", "-q",
          dist["wheel"]])
    site = _run([py, "-c", "import sysconfig; print(sysconfig.get_paths()['purelib'])"]).strip()
    import numpy  # noqa: F401  (its location is the test environment's site-packages)
    deps = os.path.dirname(os.path.dirname(numpy.__file__))
    with open(os.path.join(site, "zz_test_env_deps.pth"), "w") as f:
        f.write(deps + "\n")
    return {"python": py, "root": str(root)}


def _smoke(cmd, root, cwd):
    out = _run(cmd, cwd=cwd, env={k: v for k, v in os.environ.items() if k not in ("PYTHONPATH",)})
    vals = dict(line.split(" ", 1) for line in out.splitlines() if " " in line)
    assert vals["FILE"].startswith(root), f"exdex imported from {vals['FILE']}, not the fresh venv"
    # Fig. 3's closed form: the object slides 20 mm down (paper Section 2.2)
    assert abs(float(vals["FINAL"]) + 0.020) < 1e-9
    assert 0.0 < float(vals["VOL"]) <= 1.0   # a cone inside the Eq. 13 box of volume (1/sqrt2)^2 * 2 = 1
    return out


def test_wheel_imports_and_runs_in_a_fresh_venv(fresh_venv, tmp_path):
    print(_smoke([fresh_venv["python"], "-c", SMOKE], fresh_venv["root"], str(tmp_path)))


@pytest.mark.skipif(not sys.platform.startswith("linux") or shutil.which("unshare") is None,
                    reason="needs Linux mount namespaces (unshare)")
def test_wheel_runs_where_libgsl_cannot_be_loaded(fresh_venv, tmp_path):
    """libgsl's files are hidden (bind-mounted over with /dev/null) in a private
    mount namespace; a control import of libgsl there must fail, the wheel must not."""
    libs = set()
    for name in ("libgsl.so", "libgslcblas.so"):
        for d in ("/usr/lib/x86_64-linux-gnu", "/usr/lib/aarch64-linux-gnu", "/usr/lib64", "/usr/lib",
                  "/usr/local/lib", "/lib/x86_64-linux-gnu"):
            libs.update(os.path.realpath(p) for p in glob.glob(os.path.join(d, name + "*")))
    if not libs:
        pytest.skip("no libgsl on this machine: the fresh-venv test already ran without it")
    hide = " && ".join(f"mount --bind /dev/null {p}" for p in sorted(libs))
    probe = subprocess.run(["unshare", "--mount", "sh", "-c", "mount --make-rprivate / && " + hide + " && true"],
                           capture_output=True, text=True)
    if probe.returncode != 0:
        pytest.skip(f"cannot make a private mount namespace here: {probe.stderr.strip()[:200]}")
    py = fresh_venv["python"]
    control = subprocess.run(["unshare", "--mount", "sh", "-c", "mount --make-rprivate / && " + hide
                              + f" && {py} -c 'import ctypes; ctypes.CDLL(\"{sorted(libs)[0]}\")'"],
                             capture_output=True, text=True)
    assert control.returncode != 0, "libgsl still loads: the hiding does not work, the test would prove nothing"
    script = tmp_path / "smoke.py"
    script.write_text(SMOKE)
    out = _smoke(["unshare", "--mount", "sh", "-c", "mount --make-rprivate / && " + hide + f" && {py} {script}"],
                 fresh_venv["root"], str(tmp_path))
    print(out)
