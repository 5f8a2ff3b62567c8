#!/usr/bin/env bash
# The README's main command: install what is missing, build, and run the main job on its
# embedded default, the paper's application 2 end to end: the synthetic camera pushes
# the tracked box across the tracked table (configs/synthetic/box_push.yaml), the
# tracker (libapriltag) turns frames into poses, the simulator throws in a bunny every
# second and pushes them with the box, the renderer draws them over the frames. Real
# processes on real LCM multicast, 20 s. Writes build/demo/overlay.avi, snapshots, the
# latency report build/demo/latency.json and the processes' logs.
# Extra arguments go to the launcher (e.g. --duration 60, --tracker aruco, --record).
set -euo pipefail
cd "$(dirname "$0")/.."
tools/install_deps.sh
tools/build.sh
build/tools/scene_info/arphys-scene-info configs/scenes/bunny_box_table.yaml >/dev/null
echo "foundation check passed (scene, camera, meshes, LCM round trip): build/tools/scene_info/arphys-scene-info"
tools/arphys-launch configs/scenes/bunny_box_table.yaml --duration 20 --out build/demo "$@"
