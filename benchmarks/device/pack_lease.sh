#!/usr/bin/env bash
# Packs what benchmarks/device/nvidia_checks.sh needs on a bare NVIDIA machine into parts that each
# fit one device call beside the repository (a call carries at most 64 MiB in all): the Release
# build's binaries and every library they load (../shared/tools/gpu-bundle), dlib's landmark model
# (the fit and the landmark head box need it) and the check's data. Parts go to .gpudata/cN/part
# (ignored by git); the last lines printed are the device calls to make, back to back (a warm
# machine is given back after 30 s idle, and its /tmp with it).
# Usage: benchmarks/device/pack_lease.sh BUILD_DIR DATA_DIR
#   DATA_DIR: the team's data (../shared/data). The synthetic room capture is made here with the
#   build's `lorgnette synth` (room_matrix.sh's p_r1_y40, synth seed 1).
set -euo pipefail
if [ $# -lt 2 ]; then
  sed -n '2,10p' "$0" >&2
  exit 2
fi
build=$(realpath "$1") data=$(realpath "$2")
root=$(git rev-parse --show-toplevel)
model=/usr/share/dlib/shape_predictor_68_face_landmarks.dat
[ -f "$model" ] || { echo "pack_lease.sh: $model is missing: apt install libdlib-data" >&2 && exit 1; }
bins=(tools/lorgnette benchmarks/nerf/nerf_quality_bench benchmarks/training/bench_training
  benchmarks/nerf/bench_room_matte benchmarks/fit/bench_fit_nerf benchmarks/viewer/viewer_bench
  tests/host/field/field_test tests/host/cl_runtime_test)
for b in "${bins[@]}"; do
  [ -x "$build/$b" ] || { echo "pack_lease.sh: $build/$b is missing: build it first" >&2 && exit 1; }
done
cd "$root"
# gpu-bundle writes .git/info/exclude, which a linked worktree lacks (.git is a file there): pack in
# the checkout the device tool sends, the session's own.
[ -d .git ] || { echo "pack_lease.sh: $root is a linked worktree; run it in the main checkout" >&2 && exit 1; }
grep -qx '/.gpudata/' .git/info/exclude 2>/dev/null || echo '/.gpudata/' >>.git/info/exclude
out=$root/.gpudata
rm -rf "$out" && mkdir -p "$out/stage"

echo "pack_lease.sh: libraries and binaries (gpu-bundle; minutes on 2 cores)" >&2
extra=()
for b in "${bins[@]:1}"; do extra+=("$build/$b"); done
"$root/../shared/tools/gpu-bundle" "$build" "${extra[@]}" >&2
cat .gpu/libs-*/part >"$out/stage/libs.tar.xz"
cp .gpu/bin/bin.tar.xz "$out/stage/"  # gpu-bundle's own: the CLI and the extra binaries under bin/

echo "pack_lease.sh: dlib's landmark model" >&2
xz -T0 -6 -c "$model" >"$out/stage/dlib.dat.xz"

echo "pack_lease.sh: data" >&2
mkdir -p "$out/stage/d/lego-400"
cp -r "$data/nerf/lego-400/"{train,test,transforms_train.json,transforms_test.json} "$out/stage/d/lego-400/"
cp -r "$data/heads/in2n-face" "$data/heads/fangzhou-frontal" "$data/glasses/glasses-01" \
  "$data/glasses/glasses-06" "$out/stage/d/"
"$build/tools/lorgnette" -q synth --procedural --room 1 --views 40 --size 240x320 --yaw-range -40 40 \
  --pitch-range -10 10 --seed 1 -o "$out/stage/d/p_r1_y40"

tar -C "$out/stage" -cf "$out/all.tar" libs.tar.xz dlib.dat.xz d bin.tar.xz
rm -rf "$out/stage"
# Parts of equal size, each under the 64 MiB a call carries less the files that travel with every
# call (tracked and untracked-not-ignored), with 2 MiB to spare.
tracked=$(git ls-files -z -co --exclude-standard | xargs -0 du -cb 2>/dev/null | tail -1 | cut -f1)
room=$((64 * 1024 * 1024 - tracked - 2 * 1024 * 1024))
total=$(stat -c %s "$out/all.tar")
n=$(((total + room - 1) / room))
split -n "$n" -d -a 1 "$out/all.tar" "$out/part."
rm "$out/all.tar"
for ((i = 0; i < n; ++i)); do mkdir -p "$out/c$i" && mv "$out/part.$i" "$out/c$i/part"; done
du -sh "$out"/c* >&2
# Every call's load against the limit, as the tool counts it: the tree plus its one part.
for ((i = 0; i < n; ++i)); do
  part=$(stat -c %s "$out/c$i/part")
  load=$((tracked + part))
  printf 'call %d carries %.1f MiB of 64 (tree %.1f + part %.1f)\n' "$i" "$(bc -l <<<"$load / 1048576")" \
    "$(bc -l <<<"$tracked / 1048576")" "$(bc -l <<<"$part / 1048576")" >&2
  [ "$load" -lt $((64 * 1024 * 1024)) ] || { echo "pack_lease.sh: call $i is over 64 MiB" >&2 && exit 1; }
done
last=$((n - 1))
echo "device calls, back to back (carry .gpudata/cN in call N):"
for ((i = 0; i < last; ++i)); do echo "  $i: mkdir -p /tmp/p && cp .gpudata/c$i/part /tmp/p/$i"; done
echo "  $last: cp .gpudata/c$last/part /tmp/p/$last; mkdir -p /tmp/b /tmp/lgn; cat \$(ls -v /tmp/p/*) | tar -x -C /tmp/b;" \
  "tar -xJf /tmp/b/libs.tar.xz -C /tmp/lgn; tar -xJf /tmp/b/bin.tar.xz -C /tmp/lgn; mkdir -p /usr/share/dlib" \
  "/etc/OpenCL/vendors; xz -T0 -dc /tmp/b/dlib.dat.xz > $model;" \
  "[ -f /etc/OpenCL/vendors/nvidia.icd ] || echo libnvidia-opencl.so.1 > /etc/OpenCL/vendors/nvidia.icd;" \
  "export LD_LIBRARY_PATH=/tmp/lgn/lib PATH=/tmp/lgn/bin:\$PATH LORGNETTE_KERNEL_CACHE=/tmp/lgn/kc;" \
  "LGN_BUDGET_S=480 timeout 540 bash benchmarks/device/nvidia_checks.sh /tmp/b/d /tmp/w /tmp/res [SECTION...];" \
  "tar -czf \$OUT/res.tgz --exclude='*.lnerf' -C /tmp res"
