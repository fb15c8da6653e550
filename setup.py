"""Build of the exdex extension modules.

The numerical core (csrc/*.c, Python-free C99) is compiled into each extension
together with its hand-written CPython/NumPy wrapper (exdex/_*module.c). GSL is
found with gsl-config, or pkg-config as a fallback; without it the build stops
with a message saying how to install it.
"""
import glob
import os
import shlex
import shutil
import subprocess
import sys

import numpy
from setuptools import Extension, setup

HERE = os.path.dirname(os.path.abspath(__file__))

GSL_HELP = """
exdex needs the GNU Scientific Library (GSL) headers and library to build.
Install them, then run the install again:
  Debian/Ubuntu:  sudo apt-get install -y libgsl-dev
  Fedora:         sudo dnf install gsl-devel
  macOS:          brew install gsl
  conda:          conda install -c conda-forge gsl
(gsl-config or pkg-config must then find GSL.)
"""


def _run(cmd):
    return shlex.split(subprocess.check_output(cmd, text=True).strip())


def gsl_flags():
    """Compile and link flags for GSL, or exit with install instructions."""
    if shutil.which("gsl-config"):
        try:
            return _run(["gsl-config", "--cflags"]), _run(["gsl-config", "--libs"])
        except (OSError, subprocess.CalledProcessError):
            pass
    if shutil.which("pkg-config"):
        try:
            return _run(["pkg-config", "--cflags", "gsl"]), _run(["pkg-config", "--libs", "gsl"])
        except (OSError, subprocess.CalledProcessError):
            pass
    sys.stderr.write(GSL_HELP)
    raise SystemExit("error: GSL not found (neither gsl-config nor pkg-config knows it)")


def core_sources():
    return sorted(os.path.relpath(p, HERE) for p in glob.glob(os.path.join(HERE, "csrc", "*.c")))


def extensions():
    cflags, libs = gsl_flags()
    include_dirs = [numpy.get_include(), "csrc"]
    include_dirs += [f[2:] for f in cflags if f.startswith("-I")]
    library_dirs = [f[2:] for f in libs if f.startswith("-L")]
    libraries = [f[2:] for f in libs if f.startswith("-l")] + ["m"]
    common = dict(
        include_dirs=include_dirs,
        library_dirs=library_dirs,
        libraries=libraries,
        define_macros=[("NPY_NO_DEPRECATED_API", "NPY_1_7_API_VERSION")],
        extra_compile_args=["-std=c99", "-O2", "-D_POSIX_C_SOURCE=200809L"],
        extra_link_args=["-pthread"],  # exdex._core.simulate_batch runs POSIX threads
    )
    mods = []
    for name in ("_core", "_tool"):
        src = os.path.join("exdex", name + "module.c")
        if os.path.exists(os.path.join(HERE, src)):
            mods.append(Extension("exdex." + name, sources=[src] + core_sources(), **common))
    return mods


if __name__ == "__main__":
    setup(ext_modules=extensions())
