#!/usr/bin/env bash
# The README's test command: install what is missing, build, run the unit and
# integration tests (not `slow`); then, with clang, build the unit tests and the fuzzers
# with AddressSanitizer + UndefinedBehaviorSanitizer (build-fuzz/) and run the unit tests
# and a short smoke run of every fuzzer under them. ARPHYS_SKIP_SANITIZERS=1 skips that
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
# Ninja for new build trees, as in tools/build.sh: the sanitizer build below took 256 s with
# it against make's 308.
if command -v ninja >/dev/null; then export CMAKE_GENERATOR="${CMAKE_GENERATOR:-Ninja}"; fi
tools/build.sh -DARPHYS_BUILD_PEERS=ON   # with the peers: their oracle tests and benchmark smoke runs
(cd build && ctest -L 'unit|integration' --output-on-failure -j"$(nproc)" "$@")

if [[ -n "${ARPHYS_SKIP_SANITIZERS:-}" ]]; then exit 0; fi
if ! command -v clang++ >/dev/null; then
  echo "test.sh: clang++ missing, sanitizer and fuzz runs skipped (tools/install_deps.sh installs it)" >&2
  exit 0
fi
# File by file, not as a unity build like build/: between them the two builds check both that
# the files of a target share no file-local name and that each file includes what it uses.
# Each unit test executable runs whole, as one ctest test (a sanitized process is slow to
# start); a failure names its test case in the output. Line tables only: enough for the
# sanitizers' stack traces to name file and line, and cheaper to compile than full debug info.
cmake -S . -B build-fuzz -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ \
  -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O2 -gline-tables-only -DNDEBUG" -DCMAKE_C_FLAGS_RELWITHDEBINFO="-O2 -gline-tables-only -DNDEBUG" \
  -DARPHYS_BUILD_FUZZERS=ON -DARPHYS_BUILD_LCM_JAVA=OFF -DARPHYS_BUILD_PEERS=ON -DCMAKE_UNITY_BUILD=OFF \
  -DARPHYS_TEST_WHOLE_EXECUTABLES=ON >/dev/null
unit_tests=(geometry_test config_test msg_test msg_image_test collision_test fcl_oracle_test convex_ccd_test dynamics_test sim_process_test tracking_test
            rendering_test)
fuzzers=(fuzz_messages write_message_seeds fuzz_configs fuzz_mesh fuzz_ccd_query)
cmake --build build-fuzz -j"$(nproc)" --target "${unit_tests[@]}" "${fuzzers[@]}"
export LSAN_OPTIONS="suppressions=$PWD/tests/sanitizer/lsan.supp"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
cd build-fuzz
built="$(IFS='|'; echo "${unit_tests[*]}")"
ctest -L 'unit|fuzz' -R "^(${built}|fuzz_.*)\$" --output-on-failure -j"$(nproc)"
