"""The optional packages in tests: the physics engines a test needs (it skips
where one is not installed) and a fresh interpreter that refuses some
packages (tests/test_optional.py, tests/cli/test_dispatch.py)."""
import os
import subprocess
import sys
import textwrap

import pytest

_ENGINES_EXTRA = "(pip install .[engines])"


def need_pybullet():
    """The pybullet module, or the test skips."""
    return pytest.importorskip("pybullet", reason=f"pybullet is not installed {_ENGINES_EXTRA}")


def need_mujoco():
    """The mujoco module, or the test skips."""
    return pytest.importorskip("mujoco", reason=f"mujoco is not installed {_ENGINES_EXTRA}")


def need_drake():
    """The pydrake module, or the test skips."""
    return pytest.importorskip("pydrake", reason=f"pydrake (package drake) is not installed {_ENGINES_EXTRA}")


def need_engines():
    """All three engines (pybullet, mujoco, pydrake), or the test skips."""
    need_pybullet(), need_mujoco(), need_drake()


# A meta-path finder that raises ModuleNotFoundError for the blocked
# packages, as a missing package does; it defines BLOCKED for the code after it.
BLOCKER = textwrap.dedent("""
    import importlib.abc, sys
    BLOCKED = set({blocked!r})
    class _Blocker(importlib.abc.MetaPathFinder):
        def find_spec(self, name, path=None, target=None):
            if name.split(".")[0] in BLOCKED:
                raise ModuleNotFoundError(f"No module named {{name!r}}", name=name)
            return None
    sys.meta_path.insert(0, _Blocker())
""")


def run_without(code, blocked, *args):
    """Run code (dedented) in a fresh interpreter whose import system refuses
    the packages blocked (their top-level names), with the arguments args:
    the CompletedProcess (text stdout, stderr)."""
    src = BLOCKER.format(blocked=list(blocked)) + textwrap.dedent(code)
    env = dict(os.environ, PYTHONWARNINGS="ignore")
    return subprocess.run([sys.executable, "-c", src, *args], capture_output=True, text=True, env=env, timeout=300)
