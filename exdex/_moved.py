"""Module paths of exdex that moved into subpackages: ``import exdex.plan``,
``from exdex.hold import ...`` and the like still work and give the module
at its new path, with a DeprecationWarning naming that path.

The public names of ``exdex`` (``exdex.plan``, ``exdex.sequence``,
``exdex.tool``, ``exdex.paper`` as attributes, e.g. ``exdex.plan.solve``,
``from exdex import tool``) are not deprecated: they are the moved modules.
"""
import importlib
import importlib.abc
import importlib.machinery
import sys
import warnings

#: old module path -> new module path
MOVED = {
    "exdex.plan": "exdex.design.plan",
    "exdex.sequence": "exdex.design.sequence",
    "exdex.fit": "exdex.design.fit",
    "exdex.tool": "exdex.design.tool",
    "exdex.paper": "exdex.studies.paper",
    "exdex.bench": "exdex.studies.bench",
    "exdex.hold": "exdex.studies.hold",
    **{f"exdex.cli_{c}": f"exdex.cli.{c}" for c in ("paper", "compare", "hold", "bench", "tool", "run", "plan")},
}


def warn(old, stacklevel):
    warnings.warn(f"{old} moved to {MOVED[old]}; import it from there ({old} will be removed)",
                  DeprecationWarning, stacklevel=stacklevel + 1)


class _Loader(importlib.abc.Loader):
    """Loads an old path as the module at its new path (the same module object)."""

    def create_module(self, spec):
        warn(spec.name, 2)   # importlib's own frames are skipped: the warning points at the import
        module = importlib.import_module(MOVED[spec.name])
        self._spec = module.__spec__
        return module

    def exec_module(self, module):
        module.__spec__ = self._spec   # module_from_spec set the old path's spec: keep the module's own


class _Finder(importlib.abc.MetaPathFinder):
    def find_spec(self, fullname, path=None, target=None):
        if fullname in MOVED:
            return importlib.machinery.ModuleSpec(fullname, _Loader())
        return None


def install():
    if not any(isinstance(f, _Finder) for f in sys.meta_path):
        sys.meta_path.insert(0, _Finder())
