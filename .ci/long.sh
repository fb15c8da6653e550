#!/usr/bin/env bash
# The long run: every check of the test command (.ci/test.sh) at full depth,
# for a release or after a change to a method. Hours on a 2-core machine;
# CI runs .ci/test.sh, whose depths are chosen to keep finding the defects
# these runs found (benchmarks/README.md, "The long run").
#
#   bash .ci/long.sh            # everything below, in order
#
# 0. the C suite's random tests on 32 more seeds each (make test-salts);
# 1. valgrind memcheck with origin tracking and 1000 fuzz inputs per target
#    (CI: no origin tracking -- the same errors, without where each
#    uninitialised value came from -- and 100 inputs per target);
# 2. the fuzz driver with 10^6 inputs per target, plain and under ASan+UBSan;
# 3. pytest with 10^6 calls per entry point in the memory checks, 3000
#    Hypothesis examples per property, and the random-input zoo over seeds
#    0..999 (CI: 10^5 calls, 100 examples, seeds 0..99);
# 4. the scene zoo's long run, 10,000 scenes (benchmarks/zoo_long.py).
set -uo pipefail
cd "$(dirname "$0")/.."
bash .ci/setup.sh || exit 1
fail=0
step() { echo "== $*"; "$@" || { echo "FAILED: $*"; fail=1; }; }

step make -s -C csrc test
step make -s -C csrc test-salts
step make -s -C csrc valgrind-long
step make -s -C csrc fuzz-long
step make -s -C csrc fuzz-asan FUZZ_QUICK_N=1000000
step env EXDEX_HARDENING_CALLS=1000000 EXDEX_HYPOTHESIS_EXAMPLES=3000 ZOO_INPUTS_SEEDS=0:1000 \
  .venv/bin/python -m pytest -q
step .venv/bin/python benchmarks/zoo_long.py --n 10000 --seed 0 --jobs 2 --csv zoo_long.csv
exit $fail
