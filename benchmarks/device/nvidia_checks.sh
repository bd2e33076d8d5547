#!/usr/bin/env bash
# The NVIDIA checks of one device lease, as one command. A lease is short, so every step runs under
# `timeout`, every limit is also cut to what is left of the whole run's budget (LGN_BUDGET_S), and a
# step that fails, runs out or finds no time left is recorded in steps.csv, not fatal. Sections, run
# in the order given (default: issue 45's check, tests kernels demo real frames viewer lego pocl):
#   tests    the field and runtime unit tests on the GPU: the GPU kernels (the MLP weight gradient's
#            split among them, and NVIDIA's native float add) against the CPU kernels and references;
#   kernels  bench_training per-kernel times at 2^18 samples per step, lego and in2n-face (as `train`
#            plans it), each with the MLP weight gradient split from the compute units and with the
#            old fixed 128 work-groups (--grad-groups 128), side by side;
#   room     issue 13 on the GPU: a synthetic room capture (synthesized on the team machine) trained
#            at the product's GPU default, scored against the true mattes and fitted against the
#            mesh's ground truth (not in the default list);
#   real     a real capture to a fitted try-on (in2n-face and fangzhou-frontal: train with the
#            product's defaults, fit glasses-01), timed;
#   lego     lego-400 held-out PSNR after 5, 15 and 60 s of training (the product's sizing and GPU
#            batch of 2^18), all 200 test views;
#   demo     `lorgnette demo`, timed (its head, frame and placement feed frames and viewer);
#   frames   the paper's Table 1: `lorgnette bench frames --compare` at 480p, 720p and 1080p, head
#            alone and with glasses, the fused (auto) and the wavefront marcher frame by frame in
#            turn, on the demo head with its fitted frame and on the in2n-face avatar with glasses-01
#            as `fit` placed it (the demo and real sections' outputs; made here when missing);
#   viewer   the viewer's render path at 1920x1080 over WebSockets without a browser (viewer_bench):
#            coarse frames per second while dragging, full stills per second back to back (idle
#            delay 0), latencies;
#   pocl     PoCL on the machine's CPU cores (its image has PoCL: device 0 there): bench_training on
#            lego at 2 and 16 threads at 2^16 (the CPU's batch).
# --tiny: the same sections end to end at tiny sizes, step counts and durations (a dry run of the
# script on any OpenCL device, PoCL included; its figures measure nothing).
# Usage: benchmarks/device/nvidia_checks.sh [--tiny] DATA_DIR WORK_DIR OUT_DIR [SECTION...]
#   DATA_DIR holds lego-400/, in2n-face/, fangzhou-frontal/, glasses-01/, glasses-06/ (and
#   p_r1_y40/ for room: room_matrix.sh's synth command, seed 1); lorgnette, nerf_quality_bench,
#   bench_training, bench_room_matte, bench_fit_nerf, viewer_bench, field_test and cl_runtime_test
#   are on PATH. Environment: LGN_BUDGET_S (seconds for the whole run; default 480, --tiny 3000),
#   LGN_DEVICE (the device `bench frames` times; default: the first GPU, else device 0).
# Writes OUT_DIR/steps.csv (step, exit status, seconds; rc 'skip' when no time was left), one log
# per step and each benchmark's CSVs (frames_*/frames-*.csv, viewer_1080p/summary.csv, ...).
set -uo pipefail
tiny=0
if [ "${1:-}" = "--tiny" ]; then
  tiny=1
  shift
fi
if [ $# -lt 3 ]; then
  sed -n '2,38p' "$0" >&2
  exit 2
fi
data=$(realpath -m "$1") work=$(realpath -m "$2") out=$(realpath -m "$3")
shift 3
sections=("$@")
[ ${#sections[@]} -gt 0 ] || sections=(tests kernels demo real frames viewer lego pocl)
mkdir -p "$work" "$out"
echo "step,rc,seconds" >"$out/steps.csv"
budget=${LGN_BUDGET_S:-$((tiny ? 3000 : 480))}
deadline=$(($(date +%s) + budget))

# step NAME LIMIT_S COMMAND...: runs COMMAND under a time limit (cut to what is left of the budget),
# logs it, records rc and seconds.
step() {
  local name=$1 limit=$2
  shift 2
  local left=$((deadline - $(date +%s)))
  left=$((left - 15))  # the kill's grace below
  [ "$limit" -le "$left" ] || limit=$left
  if [ "$limit" -lt 5 ]; then
    echo "== $name: skipped, ${left} s of the budget left"
    echo "$name,skip,0" >>"$out/steps.csv"
    return
  fi
  echo "== $name (limit ${limit} s): $*"
  local t0 t1
  t0=$(date +%s%N)
  # -k: a command that takes SIGTERM as "finish the current stage" (train, fit) is killed 15 s later.
  timeout -k 15 "$limit" "$@" >"$out/$name.log" 2>&1
  local rc=$?
  t1=$(date +%s%N)
  awk -v n="$name" -v rc=$rc -v a="$t0" -v b="$t1" 'BEGIN { printf "%s,%s,%.2f\n", n, rc, (b - a) / 1e9 }' >>"$out/steps.csv"
  tail -n 3 "$out/$name.log"
}

# Sizes: the real check, or --tiny's (the same commands, small enough for 2 CPU cores).
if [ $tiny = 1 ]; then
  batch=12 sizes=96x54,128x72,192x108 repeats=1 viewer_size=192x108 viewer_s=2 lego_s=(3) eval_views=2
  train_tiny=(--steps 30 --max-side 64) bench_tiny=(--max-side 50 --warmup 2 --steps 2)
  fit_tiny=(--views 4) pocl_threads=1,2 pocl_batch=12
  demo_args=(--quick --train-steps 60 --views 8 --image-size 64 --orbit-frames 2 --orbit-size 64 --fit-views 4)
  tests_filter=(--gtest_filter='MlpGradSplit.*:Mlp.*:MlpGpuChain.*')
else
  batch=18 sizes=854x480,1280x720,1920x1080 repeats=5 viewer_size=1920x1080 viewer_s=10 lego_s=(5 15 60)
  eval_views=200 train_tiny=() bench_tiny=() fit_tiny=() pocl_threads=2,16 pocl_batch=16 demo_args=()
  tests_filter=()
fi
# The device `bench frames` times (it times every device unless told): the first GPU, else device 0.
dev=${LGN_DEVICE:-$(lorgnette devices 2>/dev/null | sed -n 's/^[* ] \[\([0-9]*\)\].*, GPU, .*/\1/p' | head -1)}
dev=${dev:-0}

nvidia-smi --query-gpu=name,driver_version,memory.total,clocks.max.sm --format=csv >"$out/gpu.csv" 2>&1
nproc >>"$out/gpu.csv"
step devices 60 lorgnette devices

tests() {
  step tests_field 150 field_test "${tests_filter[@]}"
  step tests_runtime 60 cl_runtime_test
}

kernels() {
  local b=(--batch-log2 "$batch" "${bench_tiny[@]}")
  step kernels_lego 90 bench_training --data "$data/lego-400" --out "$out/kernels_lego" "${b[@]}"
  step kernels_lego_g128 90 bench_training --data "$data/lego-400" --out "$out/kernels_lego_g128" "${b[@]}" \
    --grad-groups 128
  step kernels_in2n 90 bench_training --data "$data/in2n-face" --out "$out/kernels_in2n" "${b[@]}" --as-train
  step kernels_in2n_g128 90 bench_training --data "$data/in2n-face" --out "$out/kernels_in2n_g128" "${b[@]}" \
    --as-train --grad-groups 128
}

room() {
  local room=$data/p_r1_y40
  step room_train 150 lorgnette train "$room" -o "$work/room.lnerf" --seed 1337 --background on --force \
    "${train_tiny[@]}"
  step room_matte 120 bench_room_matte "$out/room" --case gpu_default "$work/room.lnerf" "$room" --sheet-views 1
  step room_fit 120 bench_fit_nerf "$out/room_fit" --case gpu_default "$work/room.lnerf" "$room" \
    --glasses "$data/glasses-06/scene.gltf" --variants default --repeats 1 --no-profile
}

real_one() {
  local who=$1
  step "real_train_$who" 120 lorgnette train "$data/$who" -o "$work/$who.lnerf" --force "${train_tiny[@]}"
  step "real_fit_$who" 90 lorgnette fit "$work/$who.lnerf" --glasses "$data/glasses-01/scene.gltf" \
    -o "$out/${who}_placement.json" --force "${fit_tiny[@]}"
}

real() {
  for who in in2n-face fangzhou-frontal; do real_one "$who"; done
}

lego() {
  for s in "${lego_s[@]}"; do
    step "lego_${s}s" $((s + 90)) nerf_quality_bench --data "$data/lego-400" --out "$out/lego" \
      --label "lego_${s}s" --seconds "$s" --eval-every "$s" --eval-views "$eval_views" --batch-log2 "$batch" \
      ${bench_tiny[@]:+--max-side 50}
  done
}

demo() {
  step demo 240 lorgnette demo -o "$work/demo" --force "${demo_args[@]}"
  cp "$work/demo/"*.json "$out/" 2>/dev/null || true
}

# The inputs of frames and viewer, made here when their sections did not run first.
need_demo() { [ -f "$work/demo/head.lnerf" ] || demo; }
need_in2n() { [ -f "$work/in2n-face.lnerf" ] || real_one in2n-face; }

# bench_frames NAME MODEL GLASSES PLACEMENT: Table 1, fused (auto) and wavefront side by side.
bench_frames() {
  local name=$1 model=$2 glasses=$3 placement=$4 p=()
  # Without a placement (the fit failed) the rows use bench frames' rough automatic placement.
  [ -f "$placement" ] && p=(--placement "$placement")
  step "$name" 150 lorgnette --device "$dev" bench frames --model "$model" --glasses "$glasses" "${p[@]}" \
    --compare --marcher auto,wavefront --sizes "$sizes" --repeats "$repeats" --out "$out/$name" --force
}

frames() {
  need_demo
  need_in2n
  bench_frames frames_demo "$work/demo/head.lnerf" "$work/demo/frame.glb" "$work/demo/placement.json"
  bench_frames frames_in2n "$work/in2n-face.lnerf" "$data/glasses-01/scene.gltf" "$out/in2n-face_placement.json"
}

viewer() {
  need_demo
  local p=()
  [ -f "$work/demo/placement.json" ] && p=(--placement "$work/demo/placement.json")
  step viewer_1080p 90 viewer_bench --model "$work/demo/head.lnerf" --glasses "$work/demo/frame.glb" "${p[@]}" \
    --size "$viewer_size" --skip-load --trials 5 --drag-seconds "$viewer_s" --stills-seconds "$viewer_s" \
    --idle-ms 0 --out "$out/viewer_1080p"
}

pocl() {
  step pocl_scaling 240 bench_training --data "$data/lego-400" --out "$out/pocl_scaling" --device Portable \
    --batch-log2 "$pocl_batch" --threads "$pocl_threads" ${bench_tiny[@]:+--max-side 50 --warmup 2 --steps 2}
}

for section in "${sections[@]}"; do
  case $section in
    tests | kernels | room | real | lego | demo | frames | viewer | pocl) "$section" ;;
    *) echo "unknown section '$section' (tests, kernels, room, real, lego, demo, frames, viewer, pocl)" >&2 ;;
  esac
done
cat "$out/steps.csv"
