#!/usr/bin/env bash
# Installs exactly the Debian 12 packages arphys needs, and nothing when they are
# all present (idempotent; safe to run on every build).
#   tools/install_deps.sh            build + tests + benchmarks
#   tools/install_deps.sh --print    list the packages and exit
set -euo pipefail

build=(
  build-essential cmake ninja-build pkg-config git
  liblcm-dev liblcm-bin liblcm-java libglib2.0-dev   # LCM 1.3.1; lcm.pc needs glib
  default-jdk-headless                               # javac/jar for the lcm-spy jar of our types
  libeigen3-dev libyaml-cpp-dev libassimp-dev libcli11-dev nlohmann-json3-dev
  libopencv-dev libopencv-contrib-dev libapriltag-dev libosmesa6-dev
  libmeshoptimizer-dev                               # tools/models/decimate-quadric (collision meshes)
  libbullet-extras-dev libqhull-dev                  # tools/models/convex-decompose (HACD clusters, qhull hulls)
  libtbb-dev                                         # the simulator's worker threads (--threads)
  libwebsocketpp-dev libboost-dev                    # arphys-view's Foxglove WebSocket server (Boost.Asio)
  nodejs                                             # arphys-view's page: three.js from npm (tools/view/web)
)
tests=(googletest libgtest-dev libgmock-dev iproute2 clang libclang-rt-14-dev  # clang: sanitizers + libFuzzer
       clang-format                                                             # tools/check_format.py
       libccd-dev                                                               # the convex CCD's GJK oracle
       chromium                                                                 # the view page's screenshot test
       visp-images-data)                                                        # a real photo of twelve tags, with ViSP's poses
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

# The page's and the protocol test's node packages (tools/view/web/package-lock.json) from the
# npm registry into tools/view/web/node_modules (not in the repository), when they changed.
web_packages() {
  local web
  web="$(cd "$(dirname "$0")/view/web" && pwd)"
  if [[ ! -f "$web/node_modules/.package-lock.json" || "$web/package-lock.json" -nt "$web/node_modules/.package-lock.json" ]]; then
    echo "install_deps: npm packages for tools/view/web"
    (cd "$web" && npm ci --no-audit --no-fund --loglevel=error)
  fi
}

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
# npm: Debian's package, unless a node install already brings its own.
command -v npm >/dev/null || missing+=(npm)
if [[ ${#missing[@]} -eq 0 ]]; then
  echo "install_deps: all ${#packages[@]} packages present"
  web_packages
  exit 0
fi
echo "install_deps: installing ${#missing[@]} missing packages: ${missing[*]}"
sudo_cmd=()
[[ $(id -u) -ne 0 ]] && sudo_cmd=(sudo)
export DEBIAN_FRONTEND=noninteractive
"${sudo_cmd[@]}" apt-get update -qq
"${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"
web_packages
