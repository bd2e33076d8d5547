#!/usr/bin/env bash
# Installs the Debian 12 packages Lorgnette needs to build, test and run (run as root or with sudo).
set -euo pipefail
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
PACKAGES=(
  build-essential cmake ninja-build pkg-config git
  # OpenCL: ICD loader, headers, and PoCL (the CPU device used by tests and CI)
  ocl-icd-opencl-dev opencl-c-headers opencl-clhpp-headers pocl-opencl-icd clinfo
  # geometry, images, video, ray tracing, landmarks
  libeigen3-dev libopenimageio-dev openimageio-tools libopencv-dev ffmpeg
  libembree-dev libassimp-dev libdlib-dev libdlib-data
  # camera poses from photos (`lorgnette capture`)
  colmap
  # command line, JSON, logging, tests, benchmarks
  libcli11-dev nlohmann-json3-dev libspdlog-dev libfmt-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  # the browser viewer (`lorgnette view`): Beast/Asio headers, JPEG frames; Chromium + node/npm for its e2e test
  libboost-dev libturbojpeg0-dev chromium nodejs
  # the try-on service (`lorgnette serve`): its job store (SQLite; libpq-dev for PostgreSQL, and the
  # postgresql server its tests start in a temporary folder), token hashing
  libsqlite3-dev libpq-dev postgresql libssl-dev
  # its Slurm executor's tests start a one-node cluster (slurmctld, slurmd, the clients) with munge
  slurm-wlm munge
  # the Python bindings (python/) and their tests
  pybind11-dev python3-dev python3-numpy python3-pytest
  # the .deb (dpkg-shlibdeps), the parser fuzzers (clang's libFuzzer) and the format check
  dpkg-dev clang libclang-rt-14-dev clang-format
)
if [ -z "${LORGNETTE_SKIP_APT_UPDATE:-}" ]; then $SUDO apt-get update -q; fi
$SUDO apt-get install -y -q --no-install-recommends "${PACKAGES[@]}"
# npm: Debian's package, unless the installed nodejs already brings its own (NodeSource's nodejs
# includes npm and conflicts with Debian's npm package).
if ! command -v npm > /dev/null; then $SUDO apt-get install -y -q --no-install-recommends npm; fi
