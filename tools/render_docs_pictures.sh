#!/usr/bin/env bash
# Draws the paper's two scenes over synthetic camera frames for docs/renderer.md:
#   docs/results/render/application1_spoon_teacup.png  (the teacup over the approaching spoon)
#   docs/results/render/application2_bunnies.png       (bunnies20 simulated 1.5 s, over the box frame)
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="${ARPHYS_BUILD_DIR:-$root/build}"
out="$root/docs/results/render"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
mkdir -p "$out"
cam="$build/tools/synthetic_camera/arphys-synthetic-camera"
renderer="$build/renderer/app/renderer"

"$cam" "$root/configs/synthetic/spoon_approach.yaml" --fast --no-lcm --folder "$work/spoon" --frames 61
"$renderer" --scene "$root/configs/scenes/spoon_teacup.yaml" --background "$work/spoon/frame_000060.png" \
  --look-at "0.05 -0.35 0.3 0.05 0 0.04" --proxies --out "$out/application1_spoon_teacup.png"

"$build/simulator/simulate/simulate" "$root/configs/scenes/bunnies20.yaml" --duration 1.5 --csv "$work/bunnies.csv"
"$cam" "$root/configs/synthetic/bunnies20_box.yaml" --fast --no-lcm --folder "$work/box" --frames 46
"$renderer" --scene "$root/configs/scenes/bunnies20.yaml" --camera "$root/configs/cameras/synthetic_640x480.yaml" \
  --background "$work/box/frame_000045.png" --look-at "0 -0.95 0.75 0 0 0" --states "$work/bunnies.csv" --time 1.5 \
  --out "$out/application2_bunnies.png"
echo "pictures: $out/application1_spoon_teacup.png $out/application2_bunnies.png"
