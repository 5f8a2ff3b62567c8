#!/usr/bin/env bash
# Installs exactly the Debian 12 packages arphys needs, and nothing when they are
# all present (idempotent; safe to run on every build).
#   tools/install_deps.sh            build + tests + benchmarks
#   tools/install_deps.sh --print    list the packages and exit
set -euo pipefail

build=(
  build-essential cmake pkg-config git
  liblcm-dev liblcm-bin liblcm-java libglib2.0-dev   # LCM 1.3.1; lcm.pc needs glib
  default-jdk-headless                               # javac/jar for the lcm-spy jar of our types
  libeigen3-dev libyaml-cpp-dev libassimp-dev libcli11-dev nlohmann-json3-dev
  libopencv-dev libopencv-contrib-dev libapriltag-dev libosmesa6-dev
  libmeshoptimizer-dev                               # tools/models/decimate-quadric (collision meshes)
  libbullet-extras-dev libqhull-dev                  # tools/models/convex-decompose (HACD clusters, qhull hulls)
  libtbb-dev                                         # the simulator's worker threads (--threads)
)
tests=(googletest libgtest-dev libgmock-dev iproute2 clang libclang-rt-14-dev  # clang: sanitizers + libFuzzer
       clang-format                                                             # tools/check_format.py
       libccd-dev)                                                              # the convex CCD's GJK oracle
benchmarks=(libbenchmark-dev libfcl-dev libbullet-dev libmujoco-dev libode-dev gnuplot-nox python3
            libvisp-detection-dev)                                                     # the tracker benchmark's peer (ViSP 3.5)
packages=("${build[@]}" "${tests[@]}" "${benchmarks[@]}")

if [[ "${1:-}" == "--print" ]]; then
  printf '%s\n' "${packages[@]}"
  exit 0
fi
if [[ "${1:-}" == "-h" || "${1:-}" == "--help" ]]; then
  sed -n '2,6p' "$0"
  exit 0
fi

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [[ ${#missing[@]} -eq 0 ]]; then
  echo "install_deps: all ${#packages[@]} packages present"
  exit 0
fi
echo "install_deps: installing ${#missing[@]} missing packages: ${missing[*]}"
sudo_cmd=()
[[ $(id -u) -ne 0 ]] && sudo_cmd=(sudo)
export DEBIAN_FRONTEND=noninteractive
"${sudo_cmd[@]}" apt-get update -qq
"${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"
