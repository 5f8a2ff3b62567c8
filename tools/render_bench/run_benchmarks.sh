#!/usr/bin/env bash
# Runs the render benchmark of docs/renderer.md and draws its chart.
#   tools/render_bench/run_benchmarks.sh
# Writes docs/results/render/render_bench.{csv,txt} and render_bench.png.
set -euo pipefail
source "$(dirname "$0")/../bench_common.sh"
bench_setup render arphys-render-bench
"$bench" --out "$out" "$@" | tee "$out/render_bench.txt"
gnuplot -e "outdir='$out'" "$root/tools/render_bench/render_chart.gp"
echo "chart: $out/render_bench.png" >&2
