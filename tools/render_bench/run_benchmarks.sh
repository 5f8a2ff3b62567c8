#!/usr/bin/env bash
# Runs the render benchmark of docs/renderer.md and draws its chart.
#   tools/render_bench/run_benchmarks.sh
# Writes docs/results/render/render_bench.{csv,txt} and render_bench.png.
set -euo pipefail
root="$(cd "$(dirname "$0")/../.." && pwd)"
build="${ARPHYS_BUILD_DIR:-$root/build}"
out="$root/docs/results/render"
mkdir -p "$out"
bench="$build/tools/render_bench/arphys-render-bench"
if [[ ! -x "$bench" ]]; then
  cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=Release >/dev/null
  cmake --build "$build" --target arphys-render-bench -j"$(nproc)"
fi
"$bench" --out "$out" "$@" | tee "$out/render_bench.txt"
gnuplot -e "outdir='$out'" "$root/tools/render_bench/render_chart.gp"
echo "chart: $out/render_bench.png" >&2
