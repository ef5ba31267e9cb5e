#!/usr/bin/env bash
# Quick start for a fresh Debian 12 machine (run as root, or with sudo available).
#   deploy/quickstart.sh demo   install deps, build, render the demo scene to an image
#   deploy/quickstart.sh test   install deps, build, run every test
set -euo pipefail
cd "$(dirname "$0")/.."
mode="${1:-demo}"
build_dir="${TESSERA_BUILD_DIR:-build}"

deploy/install-deps.sh

jobs="$(nproc)"
cmake -S . -B "$build_dir" -DCMAKE_BUILD_TYPE=RelWithDebInfo >/dev/null
cmake --build "$build_dir" -j "$jobs"

case "$mode" in
  demo)
    out="$PWD/$build_dir/tessera-demo.png"
    "$build_dir/samples/tutorial/tessera-tutorial" --step 10 --width 1024 --height 768 --out "$out"
    echo "Rendered the demo scene to $out"
    ;;
  test)
    cd "$build_dir"
    ctest --output-on-failure -j "$jobs"
    ;;
  *)
    echo "usage: $0 demo|test" >&2
    exit 2
    ;;
esac
