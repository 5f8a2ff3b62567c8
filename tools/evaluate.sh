#!/usr/bin/env bash
# The whole evaluation in one command (docs/EVALUATION.md):
#   tools/evaluate.sh [--quick]
# Runs every benchmark and study with the peers (FCL, Bullet, ODE, MuJoCo) in the same
# run, writes CSV and charts under docs/results/eval/, and regenerates
# docs/EVALUATION.md from them. --quick: fewer queries, frames and seconds (about 3
# minutes on 2 cores); without it, the full run (about an hour). Run
# tools/install_deps.sh first on a fresh machine. The per-stage documents
# (docs/ccd.md, dynamics.md, ...) keep their own results; nothing here overwrites them.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="${ARPHYS_BUILD_DIR:-$root/build}"
out="$root/docs/results/eval"
quick=0
[[ "${1:-}" == "--quick" ]] && quick=1
[[ "${1:-}" == "--help" || "${1:-}" == "-h" ]] && { sed -n 2,10p "$0"; exit 0; }
n() { if ((quick)); then echo "$2"; else echo "$1"; fi; }
command -v gnuplot >/dev/null || { echo "gnuplot missing: run tools/install_deps.sh" >&2; exit 1; }

started="$(date -u '+%Y-%m-%d %H:%M UTC')"
t0=$(date +%s)
step() { echo "== [$(( $(date +%s) - t0 )) s] $*" >&2; }

step "build (Release, $build)"
cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=Release -DARPHYS_BUILD_PEERS=ON >/dev/null
cmake --build "$build" -j"$(nproc)" --target arphys-ccd-bench arphys-dyn-bench arphys-track-bench arphys-render-bench \
  arphys-eval-studies arphys-launch arphys-synthetic-camera tracker arphys-simulator renderer >/dev/null
rm -rf "$out"
mkdir -p "$out"/{ccd,dyn,track,render}
timings="$out/section_seconds.csv"
echo "section,seconds" > "$timings"
section() {  # name, command...
  local name="$1" s
  shift
  s=$(date +%s)
  step "$name"
  "$@"
  echo "$name,$(( $(date +%s) - s ))" >> "$timings"
}

models="$root/configs/models"
ccd() {
  "$build/tools/ccd_bench/arphys-ccd-bench" --label "bunny 5k vs bunny 5k" --queries "$(n 1000 300)" \
    --truth-samples "$(n 2000 500)" --csv "$out/ccd/ccd_queries.csv" --summary "$out/ccd/ccd_bunny5k.csv" \
    > "$out/ccd/ccd_bunny5k.txt"
  "$build/tools/ccd_bench/arphys-ccd-bench" tunnelling --flights "$(n 200 20)" --csv "$out/ccd/ccd_tunnelling.csv" \
    > "$out/ccd/ccd_tunnelling.txt"
  gnuplot -e "summary='$out/ccd/ccd_bunny5k.csv'; tunnelling='$out/ccd/ccd_tunnelling.csv'; outdir='$out/ccd'" \
    "$root/tools/ccd_bench/ccd_charts.gp"
  rm -f "$out/ccd/ccd_queries.csv"  # per-query rows: large, and the summary holds the figures
}
dynamics() {
  local q=()
  ((quick)) && q=(--quick)
  "$build/tools/dyn_bench/arphys-dyn-bench" --scenes push,drop,bunnies "${q[@]}" --out "$out/dyn" > "$out/dyn/dyn_bench.txt"
  gnuplot -e "drop='$out/dyn/dyn_drop.csv'; outdir='$out/dyn'" "$root/tools/dyn_bench/dyn_charts.gp"
}
stacks() {
  # (Warm-started, the iterative solver keeps every stack up at 1-20 ms: --quick runs it too.)
  local engines=arphys,arphys-iterative,bullet,ode-step,ode-quick,mujoco-newton,mujoco-pgs,mujoco-cg
  ((quick)) || engines=arphys,arphys-10um,arphys-iterative,bullet,ode-step,ode-quick,mujoco-newton,mujoco-pgs,mujoco-cg
  "$build/tools/dyn_bench/arphys-dyn-bench" --scenes stack --engines "$engines" --stack-dts 0.001,0.005,0.01,0.02 \
    --stack-seconds "$(n 60 10)" --out "$out" > "$out/dyn/dyn_stack.txt"
}
tracker() {
  local q=()
  ((quick)) && q=(--quick)
  "$build/tools/track_bench/arphys-track-bench" "${q[@]}" --out "$out/track" > "$out/track/track_bench.txt"
  python3 "$root/tools/track_bench/track_tables.py" "$out/track"
  gnuplot -e "outdir='$out/track'" "$root/tools/track_bench/track_charts.gp"
}
renderer() {
  "$build/tools/render_bench/arphys-render-bench" --out "$out/render" > "$out/render/render_bench.txt"
  gnuplot -e "outdir='$out/render'" "$root/tools/render_bench/render_chart.gp"
}
end_to_end() {
  local csv="$out/eval_end_to_end.csv" dir
  echo "tracker,policy,latency_p50_ms,latency_p95_ms,registration_p50_px,registration_p95_px,frames,renderer_wait_ms,own_state_frames" > "$csv"
  # Each tracker and tracking policy with the renderer drawing at once (an earlier frame's
  # world state); then libapriltag with the renderer waiting for each frame's own.
  for run in apriltag:delay:0 apriltag:extrapolate:0 aruco:delay:0 aruco:extrapolate:0 apriltag:delay:40 apriltag:extrapolate:40; do
    IFS=: read -r tracker policy wait <<< "$run"
    dir="$out/e2e_${tracker}_${policy}_${wait}"
    ARPHYS_BUILD_DIR="$build" "$root/tools/arphys-launch" "$root/configs/scenes/bunny_box_table.yaml" \
      --duration "$(n 30 10)" --tracker "$tracker" --tracking-policy "$policy" --renderer-wait-ms "$wait" \
      --out "$dir" > "$dir.log" 2>&1
    python3 - "$dir/latency.json" "$tracker" "$policy" "$wait" >> "$csv" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
e, g, f = r["stages"]["capture_to_overlay"], r["registration"], r["frames"]
print(f'{sys.argv[2]},{sys.argv[3]},{e["p50_ms"]},{e["p95_ms"]},{g["p50_px"]},{g["p95_px"]},{g["count"]},{sys.argv[4]},'
      f'{f["rendered_with_own_world_state"]}')
PY
    rm -rf "$dir" "$dir.log"  # the video and logs of each run are not kept
  done
}
studies() {
  local q=()
  ((quick)) && q=(--quick)
  for study in tracking-map loss-flip model-size main-job-load; do
    "$build/tools/eval/arphys-eval-studies" "$study" "${q[@]}" --out "$out" 2> >(tr '\r' '\n' | tail -n 1 >&2)
  done
}

section ccd ccd
section dynamics dynamics
section stacks stacks
section tracker tracker
section renderer renderer
section end_to_end end_to_end
section studies studies

command="tools/evaluate.sh$( ((quick)) && echo ' --quick')"
step "charts and docs/EVALUATION.md"
python3 "$root/tools/eval/write_evaluation.py" --dir "$out" --doc "$root/docs/EVALUATION.md" --command "$command" \
  --started "$started" --seconds "$(( $(date +%s) - t0 ))"
step "done: docs/EVALUATION.md"
