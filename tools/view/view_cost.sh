#!/usr/bin/env bash
# What watching a run costs: the main job (synthetic camera) run in pairs, without arphys-view
# and with it serving every topic at 30 FPS to one client (node, the official Foxglove client),
# the same length each; prints the view's CPU (% of one core) and every pipeline stage's
# p50/p99 in both runs with their ratio.
#   tools/view/view_cost.sh [--duration S] [--pairs N]     (default 20 s, 2 pairs)
# Writes docs/results/view/view_cost.{csv,txt} and view_cost.png (runs in docs/results/raw/view/).
set -euo pipefail
source "$(dirname "$0")/../bench_common.sh"
bench_setup view arphys-view
duration=20
pairs=2
while [[ $# -gt 0 ]]; do
  case "$1" in
    --duration) duration="$2"; shift 2 ;;
    --pairs) pairs="$2"; shift 2 ;;
    -h|--help) sed -n '2,8p' "$0"; exit 0 ;;
    *) echo "view_cost.sh: unknown option $1" >&2; exit 2 ;;
  esac
done
raw="$root/docs/results/raw/view"
rm -rf "$raw" && mkdir -p "$raw"
port=18790
for k in $(seq 1 "$pairs"); do
  for mode in without with; do
    echo "view_cost: pair $k of $pairs, $mode the view (${duration} s)" >&2
    if [[ "$mode" == without ]]; then
      "$root/tools/arphys-launch" --duration "$duration" --out "$raw/$mode-$k" >/dev/null 2>&1
    else
      "$root/tools/arphys-launch" --duration "$duration" --out "$raw/$mode-$k" --view "$port" >/dev/null 2>&1 &
      launch=$!
      sleep 3
      # The client stands for a viewer elsewhere: it yields to the pipeline, as the view does.
      nice -n 19 node "$root/tools/view/web/record_client.mjs" "ws://127.0.0.1:$port" "$((duration - 4))" "$raw/$mode-$k/client.json"
      wait "$launch"
    fi
  done
done
python3 "$root/tools/view/view_cost.py" "$raw" "$out" | tee "$out/view_cost.txt"
gnuplot -e "outdir='$out'" "$root/tools/view/view_cost.gp"
echo "chart: $out/view_cost.png" >&2
