#!/usr/bin/env bash
# Installs the build dependencies (Debian 12), builds Lorgnette and runs every check on the CPU
# OpenCL device (PoCL): the format check (tools/check-format.sh), a short fuzzing run of the file
# parsers (tools/fuzz.sh, 10 s per target; its report goes to build-fuzz/, a crash fails), then the
# whole test suite (ctest; extra arguments go to ctest), which includes the packaged CLI on its own
# (standalone_packaged_demo: tools/standalone-check.sh, the .deb's quick demo with the team data
# hidden). This is the README's test command and what CI runs.
set -euo pipefail
cd "$(dirname "$0")/.."
bash tools/setup-debian.sh
bash tools/check-format.sh
# A unity build of the libraries and tools (tests/ opts out): each batch of sources parses the heavy
# headers (Eigen, fmt, nlohmann/json, OpenCV) once, so this clean build costs a fifth less; a
# developer's incremental build without it recompiles less per edit. The benchmarks are not built
# here: no test runs them, and they were 400 of the build's 2900 CPU s (~200 s of a run that must
# stay under 40 minutes on 2 cores): configure with -DLORGNETTE_BUILD_BENCHMARKS=ON (README,
# "Building by hand") after changing an interface they use.
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release -DCMAKE_UNITY_BUILD=ON
cmake --build build -j "$(nproc)"
FUZZ_REPORT=build-fuzz/fuzz-short-run.md FUZZ_SLOW_IS_FATAL=0 FUZZ_THIRD_PARTY_IS_FATAL=0 bash tools/fuzz.sh 10
ctest --test-dir build --output-on-failure -j "$(nproc)" "$@"
