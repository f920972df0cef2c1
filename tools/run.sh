#!/usr/bin/env bash
# Set up, build and run humandyn on a fresh Debian 12 machine, in one command.
#   bash tools/run.sh bench   install, build, run `humandyn bench` on the embedded default model (charts in out/)
#   bash tools/run.sh test    install, build, run every test
#   bash tools/run.sh deps    only install the Debian packages
# Environment: BUILD_DIR (default build), JOBS (default: number of cores), BENCH_ARGS (extra `humandyn bench` options).
set -euo pipefail
cd "$(dirname "$0")/.."

packages=(g++ cmake ninja-build pkg-config libeigen3-dev liborocos-kdl-dev libkdl-parser-dev liburdfdom-dev
          liburdfdom-headers-dev libgtest-dev libbenchmark-dev python3 python3-matplotlib
          nlohmann-json3-dev libcli11-dev libfmt-dev)

install_deps() {
  local missing=()
  for p in "${packages[@]}"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
  done
  [ ${#missing[@]} -eq 0 ] && return 0
  local sudo=""
  [ "$(id -u)" -ne 0 ] && sudo="sudo"
  echo "installing: ${missing[*]}"
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
}

# the libFuzzer targets (-DHUMANDYN_BUILD_FUZZER=ON, docs/urdf.md) need clang and its runtime libraries
packages+=(clang libclang-rt-14-dev)

build_dir=${BUILD_DIR:-build}
jobs=${JOBS:-$(nproc)}

build() {
  cmake -S . -B "$build_dir" -G Ninja -DCMAKE_BUILD_TYPE=Release "$@"
  cmake --build "$build_dir" -j "$jobs"
}

case "${1:-}" in
  deps)
    install_deps ;;
  bench)
    install_deps
    build -DHUMANDYN_BUILD_TESTS=OFF
    mkdir -p out
    # shellcheck disable=SC2086
    "$build_dir/tools/humandyn" bench --model default --json out/bench.json --csv out ${BENCH_ARGS:-}
    # the charts, drawn from the JSON (Debian's matplotlib belongs to the system Python)
    /usr/bin/python3 tools/plot_bench.py out/bench.json out
    echo "tables above; JSON, CSV and the charts (SVG and PNG) in out/" ;;
  test)
    install_deps
    build -DHUMANDYN_BUILD_TESTS=ON
    ctest --test-dir "$build_dir" --output-on-failure --no-tests=error -j "$jobs" ;;
  *)
    echo "usage: bash tools/run.sh bench|test|deps" >&2
    exit 2 ;;
esac
