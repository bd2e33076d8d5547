#!/usr/bin/env bash
# Installs the build dependencies (Debian 12), builds Lorgnette and runs every check on the CPU
# OpenCL device (PoCL): the packaged CLI on its own (tools/standalone-check.sh: the .deb's quick demo
# with the team data hidden), then the whole test suite (ctest; extra arguments go to ctest). This is
# the README's test command and what CI runs.
set -euo pipefail
cd "$(dirname "$0")/.."
bash tools/setup-debian.sh
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release
cmake --build build -j "$(nproc)"
bash tools/standalone-check.sh build
ctest --test-dir build --output-on-failure -j "$(nproc)" "$@"
