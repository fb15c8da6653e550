#!/usr/bin/env bash
# The whole test suite: the C suite (no Python), the C suite under
# AddressSanitizer + UBSan and under valgrind memcheck (in parallel parts
# beside pytest: they use separate build folders), then pytest (which also
# runs the C suite again, cross-checks its numbers through the Python API,
# and executes the notebooks). Installs what is missing first.
#
# Depth: this is the depth CI runs. The long run (see benchmarks/README.md,
# "The long run") takes valgrind's origin tracking, more fuzz inputs and
# the zoo's longer seed ranges.
set -uo pipefail
cd "$(dirname "$0")/.."
bash .ci/setup.sh || exit 1

ci_dir=csrc/build-ci
rm -rf "$ci_dir"; mkdir -p "$ci_dir"
echo "== C suite"
make -s -C csrc test | tee "$ci_dir/native.log" || { echo "C suite failed"; exit 1; }
make -s -C csrc fuzz-driver > /dev/null || { echo "fuzz driver build failed"; exit 1; }

# The C suite under ASan + UBSan and under valgrind memcheck is a queue of
# jobs, slowest first, each with its own log in csrc/build-ci/: one worker
# takes jobs beside pytest, a second joins when pytest is done. run_tests'
# --shard splits the suite; its slowest test (certify_proofs_grip_schedule,
# about a third of the suite's time under valgrind) is a job of its own.
slowest=certify_proofs_grip_schedule
shards=8
ci_jobs=()
if command -v valgrind >/dev/null 2>&1; then
  ci_jobs+=("make -s -C csrc valgrind-tests TEST_ARGS=$slowest" "make -s -C csrc valgrind-fuzz")
fi
ci_jobs+=("make -s -C csrc asan")
if command -v valgrind >/dev/null 2>&1; then
  for k in $(seq 1 $shards); do
    ci_jobs+=("make -s -C csrc valgrind-tests 'TEST_ARGS=--skip $slowest --shard $k/$shards'")
  done
fi
echo 0 > "$ci_dir/next"
claim_job() {  # the next job's index, or failure when none is left
  (
    flock 9
    i=$(cat "$ci_dir/next")
    [ "$i" -lt ${#ci_jobs[@]} ] || exit 1
    echo $((i + 1)) > "$ci_dir/next"
    echo "$i"
  ) 9> "$ci_dir/lock"
}
ci_worker() {
  while i=$(claim_job); do
    echo "${ci_jobs[$i]}" > "$ci_dir/$i.log"
    bash -c "${ci_jobs[$i]}" >> "$ci_dir/$i.log" 2>&1
    echo $? > "$ci_dir/$i.rc"
  done
}
ci_worker &
c_pid=$!

echo "== pytest"
.venv/bin/python -m pytest -q "$@"
rc=$?
if [ $rc -eq 5 ]; then
  echo "pytest collected no tests: that is a failure of the suite, not a pass" >&2
  rc=1
fi
# NumPy's SIMD paths round some ufuncs differently in the last bit (x ** 3 in
# the zoo's sampled logs), so another CPU draws the same seeds 1 ulp apart:
# the tests on log scenes run again without AVX2/AVX-512 (a no-op where
# the CPU lacks them), an assertion that passes only by one machine's last
# bits fails here
if [ "$(uname -m)" = x86_64 ] && [ $# -eq 0 ]; then
  echo "== pytest, log scenes on NumPy's baseline SIMD path (NPY_DISABLE_CPU_FEATURES)"
  NPY_DISABLE_CPU_FEATURES="X86_V3 X86_V4 AVX512_ICL" .venv/bin/python -m pytest -q -p no:cacheprovider \
    tests/scenarios/test_sampled.py "tests/scenarios/test_zoo_inputs.py::test_event_sliding_contact_with_an_obstacle_holds_through_decisions" \
    || rc=1
fi

echo "== C suite under AddressSanitizer + UndefinedBehaviorSanitizer, and under valgrind memcheck (zero errors, zero leaks)"
ci_worker
wait $c_pid
c_failed=0
vg_passed=0
for i in "${!ci_jobs[@]}"; do
  if [ "$(cat "$ci_dir/$i.rc" 2>/dev/null)" != 0 ]; then
    tail -40 "$ci_dir/$i.log"; echo "failed: ${ci_jobs[$i]}"; c_failed=1
  elif [[ "${ci_jobs[$i]}" == *asan* ]]; then
    echo "ASan + UBSan: $(grep -E "passed, .* failed" "$ci_dir/$i.log" | tail -1)"
  elif [[ "${ci_jobs[$i]}" == *valgrind-fuzz* ]]; then
    echo "valgrind: $(grep -E "^fuzz:" "$ci_dir/$i.log" | tail -1)"
  else
    n=$(grep -E "passed, .* failed" "$ci_dir/$i.log" | tail -1 | cut -d' ' -f1)
    vg_passed=$((vg_passed + ${n:-0}))
  fi
done
if command -v valgrind >/dev/null 2>&1; then
  # the parts together must run the whole suite, each test once
  native=$(grep -E "passed, .* failed" "$ci_dir/native.log" | tail -1 | cut -d' ' -f1)
  echo "valgrind: C suite $vg_passed passed in $((shards + 1)) parts (natively $native)"
  [ "$vg_passed" = "$native" ] || { echo "valgrind's parts ran $vg_passed tests, the suite has $native"; c_failed=1; }
else
  echo "valgrind not installed: memcheck run skipped (apt-get install valgrind)"
fi
[ $c_failed -eq 0 ] || exit 1
exit $rc
