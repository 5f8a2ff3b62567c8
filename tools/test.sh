#!/usr/bin/env bash
# The README's test command: install what is missing, build, run the unit and
# integration tests (not `slow`) while, with clang and at the lowest priority, the unit tests
# and the fuzzers build with AddressSanitizer + UndefinedBehaviorSanitizer (build-fuzz/); then
# run the unit tests and a short smoke run of every fuzzer under them. ARPHYS_SKIP_SANITIZERS=1 skips that
# second part. Extra arguments go to the first ctest (e.g. -R Screw).
#   tools/test.sh --quick [CTEST ARGS]   the loop while changing code: an incremental build
#                                        and the unit tests only (no installs, no sanitizers)
set -euo pipefail
cd "$(dirname "$0")/.."
if [[ "${1:-}" == "--quick" ]]; then
  shift
  tools/build.sh -DARPHYS_BUILD_PEERS=ON
  cd build && exec ctest -L unit --output-on-failure -j"$(nproc)" "$@"
fi
tools/install_deps.sh
# Ninja for the sanitizer build's new tree too (tools/build.sh picks it for build/): 256 s
# against make's 308.
if command -v ninja >/dev/null; then export CMAKE_GENERATOR="${CMAKE_GENERATOR:-Ninja}"; fi
tools/build.sh -DARPHYS_BUILD_PEERS=ON   # with the peers: their oracle tests and benchmark smoke runs

sanitizers=yes
if [[ -n "${ARPHYS_SKIP_SANITIZERS:-}" ]]; then
  sanitizers=
elif ! command -v clang++ >/dev/null; then
  echo "test.sh: clang++ missing, sanitizer and fuzz runs skipped (tools/install_deps.sh installs it)" >&2
  sanitizers=
fi
unit_tests=(geometry_test config_test msg_test msg_image_test collision_test fcl_oracle_test convex_ccd_test dynamics_test sim_process_test tracking_test
            rendering_test)
fuzzers=(fuzz_messages write_message_seeds fuzz_configs fuzz_mesh fuzz_ccd_query)

# A unity build like build/: 338 s of compile CPU against 602 file by file
# (docs/decisions/0012-test-gate-build-time.md). Each unit test executable runs whole, as one
# ctest test (a sanitized process is slow to start); a failure names its test case in the
# output. Line tables only: enough for the sanitizers' stack traces to name file and line,
# and cheaper to compile than full debug info.
sanitizer_build() {
  cmake -S . -B build-fuzz -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ \
    -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O2 -gline-tables-only -DNDEBUG" -DCMAKE_C_FLAGS_RELWITHDEBINFO="-O2 -gline-tables-only -DNDEBUG" \
    -DARPHYS_BUILD_FUZZERS=ON -DARPHYS_BUILD_LCM_JAVA=OFF -DARPHYS_BUILD_PEERS=ON -DCMAKE_UNITY_BUILD=ON \
    -DARPHYS_TEST_WHOLE_EXECUTABLES=ON >/dev/null
  cmake --build build-fuzz -j"$(nproc)" --target "${unit_tests[@]}" "${fuzzers[@]}"
}

# The sanitizer build runs beside the tests below at the lowest priority, so it takes only the
# CPU they leave idle: the pipeline tests that run alone keep about one core of the two busy.
# Job control gives it a process group of its own, stopped whole when this script ends early
# (failed tests, Ctrl-C).
sanitizer_log=build-fuzz/build.log
sanitizer_pid=
stop_sanitizer_build() { if [[ -n "$sanitizer_pid" ]]; then kill -- "-$sanitizer_pid" 2>/dev/null || true; fi; }
trap stop_sanitizer_build EXIT
trap 'exit 130' INT
trap 'exit 143' TERM
if [[ -n "$sanitizers" ]]; then
  mkdir -p build-fuzz
  set -m
  (
    renice -n 19 "$BASHPID" >/dev/null
    sanitizer_build
  ) >"$sanitizer_log" 2>&1 &
  sanitizer_pid=$!
  set +m
  echo "test.sh: the sanitizer build runs beside the tests at nice 19 (log: $sanitizer_log)"
fi
(cd build && ctest -L 'unit|integration' --output-on-failure -j"$(nproc)" "$@")
if [[ -z "$sanitizers" ]]; then exit 0; fi
echo "test.sh: finishing the sanitizer build ($(tail -n 1 "$sanitizer_log" | cut -c1-60))"
if ! wait "$sanitizer_pid"; then
  tail -n 60 "$sanitizer_log" >&2
  echo "test.sh: the sanitizer build failed (whole log: $sanitizer_log)" >&2
  exit 1
fi
sanitizer_pid=

export LSAN_OPTIONS="suppressions=$PWD/tests/sanitizer/lsan.supp"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
cd build-fuzz
built="$(IFS='|'; echo "${unit_tests[*]}")"
ctest -L 'unit|fuzz' -R "^(${built}|fuzz_.*)\$" --output-on-failure -j"$(nproc)"
