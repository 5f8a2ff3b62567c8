#!/usr/bin/env bash
# Runs the tracker benchmark of docs/tracker.md (every detector configuration on the
# same rendered frames) and draws its charts.   tools/track_bench/run_benchmarks.sh [--quick]
# Writes docs/results/track/track_{sweep,sequence,frames}.csv, the printed table
# (track_bench.txt), the summary tables (track_tables.md) and PNG charts.
set -euo pipefail
source "$(dirname "$0")/../bench_common.sh"
bench_setup track arphys-track-bench
"$bench" --out "$out" "$@" | tee "$out/track_bench.txt"
python3 "$root/tools/track_bench/track_tables.py" "$out"
gnuplot -e "outdir='$out'" "$root/tools/track_bench/track_charts.gp"
echo "charts: $out/track_frontier.png $out/track_detection_rate.png" >&2
