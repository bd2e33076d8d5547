#!/usr/bin/env bash
# Installs the dependencies (Debian 12), builds Lorgnette and runs the built-in demo: synthesize a
# head, train its NeRF, fit a frame, render an orbit. Extra arguments go to `lorgnette demo`.
set -euo pipefail
cd "$(dirname "$0")/.."
bash tools/setup-debian.sh
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release
cmake --build build -j "$(nproc)" --target lorgnette
./build/tools/lorgnette demo -o demo-output "$@"
