#!/usr/bin/env bash
# The README's main command: install what is missing, build, and run the main job
# on its embedded default. Until the pipeline lands (issue #7) the main job is the
# foundation's end-to-end check: load the bunny_box_table scene and its camera,
# check every model, compute the bunnies' mass properties, and round-trip the
# initial world state over real LCM multicast. Extra arguments go to that tool.
set -euo pipefail
cd "$(dirname "$0")/.."
tools/install_deps.sh
tools/build.sh
exec build/tools/scene_info/arphys-scene-info "$@"
