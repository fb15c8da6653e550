#!/usr/bin/env bash
# The whole test suite: the C suite (no Python), then pytest (which also runs
# the C suite again and cross-checks its numbers through the Python API, and
# executes the notebooks). Installs what is missing first.
set -uo pipefail
cd "$(dirname "$0")/.."
bash .ci/setup.sh || exit 1

echo "== C suite"
make -s -C csrc test || { echo "C suite failed"; exit 1; }

echo "== pytest"
.venv/bin/python -m pytest -q "$@"
rc=$?
if [ $rc -eq 5 ]; then
  echo "pytest collected no tests: that is a failure of the suite, not a pass" >&2
  exit 1
fi
exit $rc
