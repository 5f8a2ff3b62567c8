#!/usr/bin/env bash
# Runs the tracker benchmark of docs/tracker.md (every detector configuration on the
# same rendered frames) and draws its charts.   tools/track_bench/run_benchmarks.sh [--quick]
# Writes docs/results/track/track_{sweep,sequence,frames}.csv, the printed table
# (track_bench.txt), the summary tables (track_tables.md) and PNG charts.
set -euo pipefail
root="$(cd "$(dirname "$0")/../.." && pwd)"
build="${ARPHYS_BUILD_DIR:-$root/build}"
out="$root/docs/results/track"
mkdir -p "$out"
bench="$build/tools/track_bench/arphys-track-bench"
if [[ ! -x "$bench" ]]; then
  cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=Release >/dev/null
  cmake --build "$build" --target arphys-track-bench -j"$(nproc)"
fi
"$bench" --out "$out" "$@" | tee "$out/track_bench.txt"
python3 "$root/tools/track_bench/track_tables.py" "$out"
gnuplot -e "outdir='$out'" "$root/tools/track_bench/track_charts.gp"
echo "charts: $out/track_frontier.png $out/track_detection_rate.png" >&2
