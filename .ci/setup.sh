#!/usr/bin/env bash
# Installs what exdex needs, only what is missing; safe to run again.
#  1. GSL (Debian/Ubuntu: libgsl-dev via apt-get, as root or with sudo),
#  2. a virtual environment .venv with exdex built and installed in it
#     (editable, in setuptools' compat mode: a path entry, so mypy sees the typed package)
#     plus the test, plot, design, engines, dask, docs (pdoc, jupyter nbconvert) and explore extras.
set -euo pipefail
cd "$(dirname "$0")/.."

if ! command -v gsl-config >/dev/null 2>&1; then
  echo "== installing GSL (libgsl-dev)"
  if [ "$(id -u)" = 0 ]; then SUDO=""; elif command -v sudo >/dev/null; then SUDO="sudo"; else
    echo "GSL is missing and this user cannot install packages: install libgsl-dev (or your system's GSL development package) and run again" >&2
    exit 1
  fi
  if command -v apt-get >/dev/null 2>&1; then
    $SUDO apt-get update -qq
    DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq libgsl-dev >/dev/null
  else
    echo "GSL is missing and apt-get is not available: install GSL's development package (gsl-devel, brew install gsl, ...) and run again" >&2
    exit 1
  fi
fi

PY=${PYTHON:-python3}
if [ ! -x .venv/bin/python ]; then
  echo "== creating .venv"
  "$PY" -m venv .venv
fi
# Reinstall when the sources changed since the last install (stamp file).
stamp=.venv/.exdex-installed
if [ ! -f "$stamp" ] || [ -n "$(find csrc exdex setup.py pyproject.toml -newer "$stamp" \( -name '*.c' -o -name '*.h' -o -name '*.py' -o -name '*.toml' \) -print -quit)" ]; then
  echo "== installing exdex into .venv"
  .venv/bin/python -m pip install -q --upgrade pip setuptools wheel
  .venv/bin/python -m pip install -q -e ".[test,plot,design,engines,dask,docs,explore]" \
    --config-settings editable_mode=compat
  touch "$stamp"
fi
echo "== setup done: $(.venv/bin/python -c 'import exdex; print("exdex", exdex.__version__)')"
