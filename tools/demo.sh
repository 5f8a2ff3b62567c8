#!/usr/bin/env bash
# The README's main command: install what is missing, build, and run the main job
# on its embedded default. Until the pipeline lands (issue #7) the main job is:
#   1. the foundation's end-to-end check on bunny_box_table (scene, camera, models,
#      mass properties, a world state round trip over real LCM multicast);
#   2. the paper's application 2 simulated headless: 20 virtual bunnies falling onto
#      the table, pushed by the (scripted) real box, 3 s, every body's state per step
#      written to build/demo_bunnies20.csv;
#   3. the tracker on the bundled marker photos (tests/data/apriltag_photos, the
#      apriltag repository's own test images): every marker with its pose, printed.
# Extra arguments go to arphys-scene-info.
set -euo pipefail
cd "$(dirname "$0")/.."
tools/install_deps.sh
tools/build.sh
build/tools/scene_info/arphys-scene-info "$@"
echo
build/simulator/simulate/simulate configs/scenes/bunnies20.yaml --duration 3 --csv build/demo_bunnies20.csv
echo "states of every body per 10 ms step: build/demo_bunnies20.csv"
echo
build/tracker/app/tracker --camera tests/data/nominal_camera_799x533.yaml --source tests/data/apriltag_photos \
  --marker-size 0.05 --param decimate=1 --print --no-lcm
