"""The optional packages in tests: the physics engines a test needs (it skips
where one is not installed)."""
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

