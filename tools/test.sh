#!/usr/bin/env bash
# The README's test command: install what is missing, build, run the unit and
# integration tests (not `slow`). Extra arguments go to ctest (e.g. -R Screw).
set -euo pipefail
cd "$(dirname "$0")/.."
tools/install_deps.sh
tools/build.sh
cd build
ctest -L 'unit|integration' --output-on-failure -j"$(nproc)" "$@"
