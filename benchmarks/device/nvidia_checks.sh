#!/usr/bin/env bash
# The NVIDIA checks of one device lease, as one command (a lease is short: every run here is
# bounded by `timeout`, and a step that fails or runs out is recorded, not fatal). Sections, run in
# the order given (default: all, in this order):
#   tests    the field and runtime unit tests on the GPU: the GPU kernels (and NVIDIA's native float
#            add) against the CPU kernels on the same device, and finite differences;
#   kernels  bench_training per-kernel times at 2^18 samples per step: lego, and the room capture
#            and in2n-face planned as `train` plans them (--as-train: the room model too), each with
#            the native float add and with compare-and-swap (--float-add cas);
#   room     issue 13 on the GPU: a synthetic room capture (synthesized on the team machine) trained
#            at the product's GPU default, scored against the true mattes and fitted against the
#            mesh's ground truth;
#   real     a real capture to a fitted try-on (in2n-face and fangzhou-frontal: train with the
#            product's defaults, fit glasses-01), timed;
#   lego     lego-400 held-out PSNR after 5, 15 and 60 s of training (issue 17's targets; the
#            product's sizing and GPU batch of 2^18), all 200 test views;
#   demo     `lorgnette demo`, timed;
#   pocl     issue 17's PoCL scaling on the machine's CPU cores (its image has PoCL: device 0 there),
#            bench_training on lego over 1, 2, 4, 8 and 16 threads at 2^16 (the CPU's batch).
# Usage: benchmarks/device/nvidia_checks.sh DATA_DIR WORK_DIR OUT_DIR [SECTION...]
#   DATA_DIR holds lego-400/, p_r1_y40/ (room_matrix.sh's synth command, seed 1), in2n-face/,
#   fangzhou-frontal/, glasses-01/ and glasses-06/; lorgnette, nerf_quality_bench, bench_training,
#   bench_room_matte, bench_fit_nerf, field_test and cl_runtime_test are on PATH. Writes
#   OUT_DIR/steps.csv (step, exit status, seconds), one log per step and each benchmark's CSVs.
set -uo pipefail
if [ $# -lt 3 ]; then
  sed -n '2,24p' "$0" >&2
  exit 2
fi
data=$1 work=$2 out=$3
shift 3
sections=("$@")
[ ${#sections[@]} -gt 0 ] || sections=(tests kernels room real lego demo pocl)
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

tests() {
  step tests_field 120 field_test
  step tests_runtime 60 cl_runtime_test
}

kernels() {
  local room=$data/p_r1_y40
  step kernels_lego 90 bench_training --data "$data/lego-400" --out "$out/kernels_lego" --batch-log2 18
  step kernels_lego_cas 90 bench_training --data "$data/lego-400" --out "$out/kernels_lego_cas" --batch-log2 18 \
    --float-add cas
  step kernels_room 90 bench_training --data "$room" --out "$out/kernels_room" --batch-log2 18 --as-train
  step kernels_room_cas 90 bench_training --data "$room" --out "$out/kernels_room_cas" --batch-log2 18 --as-train \
    --float-add cas
  step kernels_in2n 90 bench_training --data "$data/in2n-face" --out "$out/kernels_in2n" --batch-log2 18 --as-train
}

room() {
  local room=$data/p_r1_y40
  step room_train 150 lorgnette train "$room" -o "$work/room.lnerf" --seed 1337 --background on
  step room_matte 120 bench_room_matte "$out/room" --case gpu_default "$work/room.lnerf" "$room" --sheet-views 1
  step room_fit 120 bench_fit_nerf "$out/room_fit" --case gpu_default "$work/room.lnerf" "$room" \
    --glasses "$data/glasses-06/scene.gltf" --variants default --repeats 1 --no-profile
}

real() {
  for who in in2n-face fangzhou-frontal; do
    step "real_train_$who" 120 lorgnette train "$data/$who" -o "$work/$who.lnerf"
    step "real_fit_$who" 90 lorgnette fit "$work/$who.lnerf" --glasses "$data/glasses-01/scene.gltf" \
      -o "$out/${who}_placement.json"
  done
}

lego() {
  for s in 5 15 60; do
    step "lego_${s}s" $((s + 90)) nerf_quality_bench --data "$data/lego-400" --out "$out/lego" \
      --label "lego_${s}s" --seconds "$s" --eval-every "$s" --eval-views 200 --batch-log2 18
  done
}

demo() {
  step demo 240 lorgnette demo -o "$work/demo"
  cp "$work/demo/"*.json "$out/" 2>/dev/null || true
}

pocl() {
  step pocl_scaling 300 bench_training --data "$data/lego-400" --out "$out/pocl_scaling" --device Portable \
    --batch-log2 16 --threads 1,2,4,8,16
}

for section in "${sections[@]}"; do
  case $section in
    tests | kernels | room | real | lego | demo | pocl) "$section" ;;
    *) echo "unknown section '$section' (tests, kernels, room, real, lego, demo, pocl)" >&2 ;;
  esac
done
cat "$out/steps.csv"
