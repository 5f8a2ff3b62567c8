#!/usr/bin/env bash
# Runs the CCD benchmarks of docs/ccd.md and draws their charts.
#   tools/ccd_bench/run_benchmarks.sh [--quick]
# Writes summaries and charts to docs/results/ccd/ and per-query CSVs to
# docs/results/raw/ (not committed). --quick: fewer queries, for a smoke run.
set -euo pipefail
root="$(cd "$(dirname "$0")/../.." && pwd)"
build="${ARPHYS_BUILD_DIR:-$root/build}"
out="$root/docs/results/ccd"
raw="$root/docs/results/raw"
mkdir -p "$out" "$raw"
bench="$build/tools/ccd_bench/arphys-ccd-bench"
if [[ ! -x "$bench" ]]; then
  cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=Release -DARPHYS_BUILD_PEERS=ON >/dev/null
  cmake --build "$build" --target arphys-ccd-bench -j"$(nproc)"
fi
command -v gnuplot >/dev/null || { echo "gnuplot missing: run tools/install_deps.sh" >&2; exit 1; }
source "$root/tools/bench_common.sh"
record_machine "$root" "$out"

quick=0
[[ "${1:-}" == "--quick" ]] && quick=1
n() { if ((quick)); then echo "$2"; else echo "$1"; fi; }
models="$root/configs/models"

run() {  # name, args...
  local name="$1"; shift
  echo "== $name" >&2
  "$bench" "$@" --csv "$raw/ccd_$name.csv" --summary "$out/ccd_$name.csv" | tee "$out/ccd_$name.txt"
}

run bunny5k --label "bunny 5k vs bunny 5k" --queries "$(n 1000 60)" --truth-samples "$(n 2000 500)"
run bunny70k --label "bunny 70k vs bunny 70k" --mesh-a "$models/stanford-bunny-70k.ply" \
  --queries "$(n 100 10)" --truth-samples "$(n 1000 200)"
run spoon_teacup --label "teaspoon (moving) vs teacup+saucer" --mesh-a "$models/newell-teacup.obj" \
  --mesh-b "$models/newell-teaspoon.obj" --common-scale --queries "$(n 300 30)" --truth-samples "$(n 2000 500)"
run box_bunny --label "box 0.3 x 0.2 x 0.1 (moving) vs bunny 5k" --box-b 0.3 0.2 0.1 \
  --queries "$(n 300 30)" --truth-samples "$(n 2000 500)"
echo "== tunnelling" >&2
"$bench" tunnelling --flights "$(n 200 20)" --csv "$out/ccd_tunnelling.csv" | tee "$out/ccd_tunnelling.txt"

gnuplot -e "summary='$out/ccd_bunny5k.csv'; tunnelling='$out/ccd_tunnelling.csv'; outdir='$out'" \
  "$root/tools/ccd_bench/ccd_charts.gp"
echo "charts: $out/ccd_speed_accuracy.png $out/ccd_tunnelling.png" >&2
