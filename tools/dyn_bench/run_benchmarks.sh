#!/usr/bin/env bash
# Runs the dynamics benchmark of docs/dynamics.md (arphys against Bullet, ODE, MuJoCo)
# and draws its charts.   tools/dyn_bench/run_benchmarks.sh [--quick]
# Writes docs/results/dyn/dyn_<scene>.csv, the printed tables (dyn_bench.txt) and PNGs.
set -euo pipefail
source "$(dirname "$0")/../bench_common.sh"
bench_setup dyn arphys-dyn-bench
"$bench" --out "$out" "$@" | tee "$out/dyn_bench.txt"
anchor=""
[[ -s "$out/dyn_anchor_pile.csv" ]] && anchor="; anchor='$out/dyn_anchor_pile.csv'"
bunnies=""
[[ -s "$out/dyn_bunnies_peers.csv" ]] && bunnies="; bunnies='$out/dyn_bunnies_peers.csv'"
gnuplot -e "drop='$out/dyn_drop.csv'; outdir='$out'$anchor$bunnies" "$root/tools/dyn_bench/dyn_charts.gp"
echo "charts: $out/dyn_drop_timing.png $out/dyn_accuracy_speed.png${anchor:+ $out/dyn_anchor_pile.png}${bunnies:+ $out/dyn_bunnies_peers.png}" >&2
