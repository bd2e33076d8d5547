#!/usr/bin/env bash
# Installs the build dependencies (Debian 12), builds Lorgnette and runs the whole test suite on the
# CPU OpenCL device (PoCL). This is the README's test command and what CI runs.
set -euo pipefail
cd "$(dirname "$0")/.."
bash tools/setup-debian.sh
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release
cmake --build build -j "$(nproc)"
ctest --test-dir build --output-on-failure -j "$(nproc)" "$@"
