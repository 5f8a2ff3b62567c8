# Sourced by the tools/*_bench/run_benchmarks.sh scripts:
#   bench_setup RESULTS_SUBDIR TARGET   sets root, build, out (created) and bench (built if missing),
#                                       and records the machine (record_machine, below)
bench_setup() {
  root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
  build="${ARPHYS_BUILD_DIR:-$root/build}"
  out="$root/docs/results/$1"
  mkdir -p "$out"
  bench="$(find "$build/tools" -maxdepth 2 -name "$2" -type f -perm -u+x 2>/dev/null | head -n 1)"
  if [[ -z "$bench" ]]; then
    cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=Release -DARPHYS_BUILD_PEERS=ON >/dev/null
    cmake --build "$build" --target "$2" -j"$(nproc)"
    bench="$(find "$build/tools" -maxdepth 2 -name "$2" -type f -perm -u+x | head -n 1)"
  fi
  command -v gnuplot >/dev/null || { echo "gnuplot missing: run tools/install_deps.sh" >&2; exit 1; }
  record_machine "$root" "$out"
}

#   record_machine ROOT OUTDIR   writes OUTDIR/machine.txt: when, which CPU, how many, which commit.
# These machines are shared and vary from day to day: ratios to the peers compare across
# runs, absolute times only on the same machine.
record_machine() {
  local cpu
  cpu="$(lscpu 2>/dev/null | sed -n 's/^Model name: *//p' | head -n 1)"
  printf '%s, %s, %s CPUs, commit %s\n' "$(date -u '+%F %H:%M UTC')" "${cpu:-unknown CPU}" "$(nproc)" \
    "$(git -C "$1" describe --always --dirty 2>/dev/null || echo unknown)" | tee "$2/machine.txt" >&2
}
