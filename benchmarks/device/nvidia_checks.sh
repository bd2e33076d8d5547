#!/usr/bin/env bash
# The NVIDIA checks of one device lease, as one command (a lease is short: every run here is
# bounded by `timeout`, and a step that fails or runs out is recorded, not fatal).
#   1. issue 13 on the GPU: a synthetic room capture (synthesized on the team machine) trained with
#      the room model at 2^16 x 1200 steps (the CPU matrix's budget: the GPU kernels must give the
#      CPU path's matte) and at the product's GPU default, scored against the true mattes and fitted
#      against the mesh's ground truth;
#   2. a real capture to a fitted try-on (in2n-face and fangzhou-frontal: train with the product's
#      defaults, fit glasses-01), timed;
#   3. lego-400 held-out PSNR after 5, 15 and 60 s of training (issue 17's targets; the product's
#      sizing and GPU batch of 2^18), all 200 test views;
#   4. bench_training on lego: per-kernel device time and samples/s, the GPU kernels (auto) and the
#      CPU kernels on the same GPU;
#   5. `lorgnette demo`, timed.
# Usage: benchmarks/device/nvidia_checks.sh DATA_DIR WORK_DIR OUT_DIR
#   DATA_DIR holds lego-400/, p_r1_y40/ (room_matrix.sh's synth command, seed 1), in2n-face/,
#   fangzhou-frontal/ and glasses-01/; lorgnette, nerf_quality_bench, bench_training,
#   bench_room_matte and bench_fit_nerf are on PATH. Writes OUT_DIR/steps.csv (step, exit status,
#   seconds), one log per step and each benchmark's CSVs.
set -uo pipefail
if [ $# -lt 3 ]; then
  sed -n '2,19p' "$0" >&2
  exit 2
fi
data=$1 work=$2 out=$3
mkdir -p "$work" "$out"
echo "step,rc,seconds" >"$out/steps.csv"
# step NAME LIMIT_S COMMAND...: runs COMMAND under a time limit, logs it, records rc and seconds.
step() {
  local name=$1 limit=$2
  shift 2
  echo "== $name (limit ${limit} s): $*"
  local t0 t1
  t0=$(date +%s%N)
  timeout "$limit" "$@" >"$out/$name.log" 2>&1
  local rc=$?
  t1=$(date +%s%N)
  awk -v n="$name" -v rc=$rc -v a="$t0" -v b="$t1" 'BEGIN { printf "%s,%s,%.2f\n", n, rc, (b - a) / 1e9 }' >>"$out/steps.csv"
  tail -n 3 "$out/$name.log"
}

nvidia-smi --query-gpu=name,driver_version,memory.total,clocks.max.sm --format=csv >"$out/gpu.csv" 2>&1
nproc >>"$out/gpu.csv"
step devices 60 lorgnette devices

# 1. Issue 13: a synthetic room capture.
room=$data/p_r1_y40
step room_train_b16 90 lorgnette train "$room" -o "$work/room_b16.lnerf" --steps 1200 --seed 1337 --background on \
  --batch-log2 16
step room_train_default 90 lorgnette train "$room" -o "$work/room_default.lnerf" --seed 1337 --background on
step room_matte 120 bench_room_matte "$out/room" --case gpu_b16_1200 "$work/room_b16.lnerf" "$room" \
  --case gpu_default "$work/room_default.lnerf" "$room" --sheet-views 1
step room_fit 120 bench_fit_nerf "$out/room_fit" --case gpu_b16_1200 "$work/room_b16.lnerf" "$room" \
  --case gpu_default "$work/room_default.lnerf" "$room" --variants default --repeats 1 --no-profile

# 2. Real captures to a fitted try-on, with the product's defaults.
for who in in2n-face fangzhou-frontal; do
  step "real_train_$who" 120 lorgnette train "$data/$who" -o "$work/$who.lnerf"
  step "real_fit_$who" 90 lorgnette fit "$work/$who.lnerf" --glasses "$data/glasses-01/scene.gltf" \
    -o "$out/${who}_placement.json"
done

# 3. lego: PSNR against seconds.
for s in 5 15 60; do
  step "lego_${s}s" $((s + 90)) nerf_quality_bench --data "$data/lego-400" --out "$out/lego" --label "lego_${s}s" \
    --seconds "$s" --eval-every "$s" --eval-views 200 --batch-log2 18
done

# 4. Kernels: the GPU variant (auto on a GPU) and the CPU variant on the same device.
step kernels_auto 90 bench_training --data "$data/lego-400" --out "$out/kernels_auto" --batch-log2 18
step kernels_cpu 90 bench_training --data "$data/lego-400" --out "$out/kernels_cpu" --variant cpu --batch-log2 18

# 5. The demo, end to end.
step demo 240 lorgnette demo -o "$work/demo"
cp "$work/demo/"*.json "$out/" 2>/dev/null || true
cat "$out/steps.csv"
