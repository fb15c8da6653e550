"""Optional dependencies: imported only by the feature that needs them.

``import exdex`` needs only NumPy. Plotting and progress bars need the
``plot`` extra (matplotlib, tqdm), the physics-engine cross-checks the
``engines`` extra (pybullet, MuJoCo). A feature used without its extra raises
:class:`MissingExtraError` (an ``ImportError``) whose message names the
package and the extra to install.
"""
from __future__ import annotations

import importlib

__all__ = ["MissingExtraError", "require", "available", "pyplot", "progress_bar", "EXTRAS"]

#: module -> the pip extra that installs it
EXTRAS = {
    "matplotlib": "plot",
    "tqdm": "plot",
    "scipy": "design",
    "pybullet": "engines",
    "mujoco": "engines",
    "pydrake": "engines",
}


class MissingExtraError(ImportError):
    """An optional dependency of exdex is not installed; the message says which extra installs it."""

    def __init__(self, module, feature, extra):
        self.module, self.feature, self.extra = module, feature, extra
        super().__init__(f"{feature} needs {module}, which is not installed: "
                         f"pip install 'exdex[{extra}]'", name=module)


def require(module, feature):
    """Import ``module`` for ``feature`` (a few words, e.g. "Result.plot()"),
    or raise :class:`MissingExtraError` naming the extra that installs it."""
    try:
        return importlib.import_module(module)
    except ImportError as exc:
        top = module.split(".")[0]
        # only a missing optional package itself is reported as such; an
        # ImportError raised inside an installed package propagates
        if getattr(exc, "name", None) not in (None, top, module) and not str(exc.name).startswith(top + "."):
            raise
        raise MissingExtraError(top, feature, EXTRAS.get(top, top)) from exc


def available(module):
    """True when ``module`` can be imported (without importing it)."""
    import importlib.util

    try:
        return importlib.util.find_spec(module) is not None
    except (ImportError, ValueError):
        return False


def pyplot(feature, backend=None):
    """``matplotlib.pyplot`` for ``feature``; ``backend`` (e.g. "Agg") is
    selected first when given and pyplot was not imported yet."""
    mpl = require("matplotlib", feature)
    if backend is not None:
        mpl.use(backend, force=False)
    return require("matplotlib.pyplot", feature)


class _NoBar:
    """Stands in for a disabled tqdm bar when tqdm is not installed."""

    def __init__(self, iterable=None, **_):
        self._it = iterable

    def __iter__(self):
        return iter(self._it if self._it is not None else ())

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        return False

    def update(self, n=1):
        pass

    def set_postfix_str(self, *a, **k):
        pass

    def set_description(self, *a, **k):
        pass

    def close(self):
        pass


def progress_bar(iterable=None, *, disable=False, feature="the progress bar", auto=False, **kwargs):
    """A tqdm bar (``tqdm.auto`` when ``auto``); with ``disable`` and no tqdm
    installed, a silent stand-in, so hiding the bar never needs the extra."""
    try:
        mod = require("tqdm.auto" if auto else "tqdm", feature)
    except MissingExtraError:
        if disable:
            return _NoBar(iterable)
        raise
    return mod.tqdm(iterable, disable=disable, **kwargs)
