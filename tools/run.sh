#!/usr/bin/env bash
# Set up, build and run humandyn on a fresh Debian 12 machine, in one command.
#   bash tools/run.sh bench   install, build, run `humandyn bench` on the embedded default model (charts in out/)
#   bash tools/run.sh test    install, build (the library, the command line, the tests: not the benchmarks),
#                             run every test
#   bash tools/run.sh deps    only install the Debian packages
#   bash tools/run.sh ci-deps the packages CI's further stages need besides (clang, its sanitizer runtimes,
#                             clang-format, clang-tidy)
#   bash tools/run.sh pinocchio  print the Pinocchio prefix the test command builds against (its venv made
#                             when missing; nothing printed where PyPI's `pin` cannot be had)
# Environment: BUILD_DIR (default build), JOBS (default: number of cores), BENCH_ARGS (extra `humandyn bench`
# options), HUMANDYN_WERROR (ON: warnings are errors, as in CI).
set -euo pipefail
cd "$(dirname "$0")/.."

packages=(g++ cmake ninja-build pkg-config libeigen3-dev liborocos-kdl-dev libkdl-parser-dev liburdfdom-dev
          liburdfdom-headers-dev libgtest-dev libbenchmark-dev python3 python3-venv python3-matplotlib
          nlohmann-json3-dev libcli11-dev libfmt-dev)
# only for the test command: the browser that loads `humandyn view`'s page, its WebDriver and what drives it
# (tests/view_browser.py)
test_packages=(chromium chromium-driver python3-selenium python3-pil)
ci_packages=(clang libclang-rt-14-dev clang-format clang-tidy)

install_deps() {
  local missing=()
  for p in "$@"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
  done
  [ ${#missing[@]} -eq 0 ] && return 0
  local sudo=""
  [ "$(id -u)" -ne 0 ] && sudo="sudo"
  echo "installing: ${missing[*]}"
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
}

build_dir=${BUILD_DIR:-build}
jobs=${JOBS:-$(nproc)}

# A unity build of the tests and the command line: their files compiled a few at a time as one translation
# unit, so that the engine's templates they share are instantiated once per batch (tests/CMakeLists.txt).
build() {
  cmake -S . -B "$build_dir" -G Ninja -DCMAKE_BUILD_TYPE=Release -DHUMANDYN_UNITY_BUILD=ON \
    -DHUMANDYN_WERROR="${HUMANDYN_WERROR:-OFF}" "$@"
  cmake --build "$build_dir" -j "$jobs"
}

# Pinocchio, the independent reference for the floating base and the derivatives: PyPI `pin` (its C++
# headers) in a virtual environment of the build. Where it cannot be had, the comparison says it skips.
pinocchio_prefix() {
  local venv="$build_dir/venv"
  if [ ! -x "$venv/bin/python" ]; then python3 -m venv "$venv" >&2 || return 0; fi
  "$venv/bin/python" -c "import cmeel" 2>/dev/null || "$venv/bin/python" -m pip install -q pin >&2 || return 0
  "$venv/bin/python" -c "import cmeel, os; print(os.path.join(os.path.dirname(os.path.dirname(cmeel.__file__)), 'cmeel.prefix'))"
}

case "${1:-}" in
  deps)
    install_deps "${packages[@]}" ;;
  ci-deps)
    install_deps "${ci_packages[@]}" ;;
  pinocchio)
    mkdir -p "$build_dir"
    pinocchio_prefix ;;
  bench)
    install_deps "${packages[@]}"
    build -DHUMANDYN_BUILD_TESTS=OFF
    mkdir -p out
    # shellcheck disable=SC2086
    "$build_dir/tools/humandyn" bench --model default --json out/bench.json --csv out ${BENCH_ARGS:-}
    # the charts, drawn from the JSON (Debian's matplotlib belongs to the system Python)
    /usr/bin/python3 tools/plot_bench.py out/bench.json out
    echo "tables above; JSON, CSV and the charts (SVG and PNG) in out/" ;;
  test)
    install_deps "${packages[@]}" "${test_packages[@]}"
    mkdir -p "$build_dir"
    build -DHUMANDYN_BUILD_TESTS=ON -DHUMANDYN_BUILD_BENCH=OFF -DHUMANDYN_PINOCCHIO_PREFIX="$(pinocchio_prefix)"
    ctest --test-dir "$build_dir" --output-on-failure --no-tests=error -j "$jobs" ;;
  *)
    echo "usage: bash tools/run.sh bench|test|deps|ci-deps|pinocchio" >&2
    exit 2 ;;
esac
