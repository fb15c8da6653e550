"""Build of the exdex extension modules.

The numerical core (csrc/*.c, Python-free C99) is compiled into each extension
together with its hand-written CPython/NumPy wrapper (exdex/_*module.c). GSL is
found with gsl-config, or pkg-config as a fallback; without it the build stops
with a message saying how to install it.

How GSL is linked is chosen by the environment variable ``EXDEX_GSL_LINK``:

* ``auto`` (default): statically when GSL's static libraries (libgsl.a and
  libgslcblas.a) are found in GSL's library folder, else dynamically;
* ``static``: statically, or stop with an error when the static libraries are
  missing;
* ``shared``: dynamically (the built extension then needs libgsl at run time).

A statically linked extension carries GSL inside it, so its wheel installs and
runs on machines without libgsl; GSL's symbols are kept private to it.
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


STATIC_DIRS = ("/usr/lib/x86_64-linux-gnu", "/usr/lib/aarch64-linux-gnu", "/usr/lib64", "/usr/lib",
               "/usr/local/lib", "/opt/homebrew/lib")


def link_mode():
    mode = os.environ.get("EXDEX_GSL_LINK", "auto").strip().lower() or "auto"
    if mode not in ("auto", "static", "shared"):
        raise SystemExit(f"error: EXDEX_GSL_LINK must be auto, static or shared, got {mode!r}")
    return mode


def static_archives(library_dirs, libraries):
    """Paths of lib<name>.a for every GSL library (gsl, gslcblas), or None."""
    dirs = list(library_dirs) + [d for d in STATIC_DIRS if d not in library_dirs]
    found = []
    for name in libraries:
        path = next((os.path.join(d, f"lib{name}.a") for d in dirs
                     if os.path.isfile(os.path.join(d, f"lib{name}.a"))), None)
        if path is None:
            return None
        found.append(path)
    return found


def core_sources():
    return sorted(os.path.relpath(p, HERE) for p in glob.glob(os.path.join(HERE, "csrc", "*.c")))


def extensions():
    cflags, libs = gsl_flags()
    include_dirs = [numpy.get_include(), "csrc"]
    include_dirs += [f[2:] for f in cflags if f.startswith("-I")]
    library_dirs = [f[2:] for f in libs if f.startswith("-L")]
    gsl_libs = [f[2:] for f in libs if f.startswith("-l") and f[2:] != "m"]
    link_args = ["-pthread"]  # exdex._core.simulate_batch runs POSIX threads
    mode = link_mode()
    archives = static_archives(library_dirs, gsl_libs) if mode != "shared" else None
    if mode == "static" and archives is None:
        raise SystemExit("error: EXDEX_GSL_LINK=static but GSL's static libraries (lib"
                         + ".a, lib".join(gsl_libs) + ".a) were not found in " + ", ".join(library_dirs or STATIC_DIRS))
    if archives:
        libraries = ["m"]
        if sys.platform.startswith("linux"):
            link_args += ["-Wl,--exclude-libs,ALL"]  # GSL's symbols stay private to the extension
    else:
        libraries = gsl_libs + ["m"]
    common = dict(
        include_dirs=include_dirs,
        library_dirs=library_dirs,
        libraries=libraries,
        define_macros=[("NPY_NO_DEPRECATED_API", "NPY_1_7_API_VERSION")],
        extra_compile_args=["-std=c99", "-O2", "-D_POSIX_C_SOURCE=200809L"],
        extra_objects=archives or [],  # before -lm on the link line: GSL needs libm
        extra_link_args=link_args,
    )
    mods = []
    for name in ("_core", "_tool"):
        src = os.path.join("exdex", name + "module.c")
        if os.path.exists(os.path.join(HERE, src)):
            extra = [os.path.join("exdex", "_gslstatic.c")] if archives else []
            mods.append(Extension("exdex." + name, sources=[src] + core_sources() + extra, **common))
    return mods


if __name__ == "__main__":
    setup(ext_modules=extensions())
