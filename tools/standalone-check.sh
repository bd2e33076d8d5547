#!/usr/bin/env bash
# Checks that the product runs on its own, as a user installs it: packs the .deb from BUILD_DIR
# (default build/), checks the package's declared dependencies, unpacks it into a scratch root and
# runs the packaged `lorgnette` from an empty directory outside the repository: --version, then the
# quick demo, whose report tests/demo/quick_report_check.py checks (the fit, a PSNR floor, the
# files, the stage timings). Where the system allows it (root, unshare), the team data beside the
# clone (../shared) is hidden behind an empty tmpfs for the whole run, so a read from it fails
# loudly. The ctest test standalone_packaged_demo runs it (tests/demo): the suite's one run of the
# whole quick demo.
set -euo pipefail
cd "$(dirname "$0")/.."
repo=$(pwd)
build=${1:-build}
work=$(mktemp -d /tmp/lorgnette-standalone.XXXXXX)
trap 'rm -rf "$work"' EXIT

echo "standalone: packing the .deb"
(cd "$build" && cpack -G DEB -B "$work/pkg" > "$work/cpack.log") || { cat "$work/cpack.log"; exit 1; }
deb=$(ls "$work"/pkg/lorgnette_*.deb)
depends=$(dpkg-deb -f "$deb" Depends)
echo "standalone: $(basename "$deb") depends on: $depends"
for need in libdlib-data opencl-icd libOpenImageIO libembree libassimp; do
  if ! grep -qi "$need" <<< "$depends"; then
    echo "standalone: FAILED: the package does not declare '$need'"; exit 1
  fi
done
dpkg-deb -x "$deb" "$work/root"
bin="$work/root/usr/bin/lorgnette"
test -x "$bin"
test -f "$work/root/usr/share/doc/lorgnette/licenses/mean-face-68.txt"

# The binary must not carry the path of the team data it was built beside.
shared=$(cd "$repo/.." && pwd)/shared
if grep -qF "$shared" "$bin"; then
  echo "standalone: FAILED: the binary names '$shared'"; exit 1
fi

mkdir -p "$work/run"
run='set -e; cd "$1"; "$2" --version; "$2" -q demo --quick -o demo-output'
if [ -d "$shared" ] && [ "$(id -u)" -eq 0 ] && unshare -m --propagation private true 2> /dev/null; then
  echo "standalone: running the packaged CLI with $shared hidden"
  unshare -m --propagation private bash -c "mount -t tmpfs none '$shared' && $run" _ "$work/run" "$bin"
else
  echo "standalone: running the packaged CLI (could not hide $shared: not root or no unshare)"
  bash -c "$run" _ "$work/run" "$bin"
fi
python3 tests/demo/quick_report_check.py "$work/run/demo-output"
echo "standalone: the packaged demo ran without the team data: ok"
