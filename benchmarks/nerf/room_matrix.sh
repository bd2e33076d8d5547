#!/usr/bin/env bash
# Issue 13's measurement matrix on synthetic room captures: subjects (the procedural head with neck and
# shoulders, the Lee Perry-Smith scan) x rooms (1, 2) x arcs (yaw +-40 / pitch +-10, yaw +-20 / pitch
# +-15), each synthesized, trained with the room model for the same number of steps, then scored on
# its held-out views against the true mattes (bench_room_matte: IoU, leak, holes, face PSNR, contact
# sheets) and fitted (bench_fit_nerf's `default` variant, the options `lorgnette fit` runs: nose,
# ear and rotation errors against the mesh's ground truth; until 27 Nov the matrix fitted the `fast`
# variant, which marches the views at step x1 where the product marches at x1.5; FIT_VARIANT
# (environment) picks another). Step counts, not seconds, so runs compare under any load.
# Usage: benchmarks/nerf/room_matrix.sh BUILD_DIR DATA_DIR WORK_DIR OUT_DIR [STEPS] [CASES...]
#   STEPS: training steps (default 1200), or "default" for the product's own budget (no --steps).
#   CASES: names like p_r1_y40 (p = procedural, s = scan; r1/r2 = room; y40/y20 = arc); default all 8.
# Existing datasets and models in WORK_DIR are reused (delete them to start over). Writes
# OUT_DIR/room_matte.csv, OUT_DIR/fit/fit_nerf.csv, OUT_DIR/room_matrix.csv (the two joined) and
# OUT_DIR/<case>_sheet.png. TRAIN_ARGS (environment) adds options to every `lorgnette train`; SEED
# (environment, default 1337) is its training seed; SYNTH_SEED (environment, default 1) is synth's
# (the cameras' jitter and the procedural head's shape: another seed is another person).
set -euo pipefail
if [ $# -lt 4 ]; then
  sed -n '2,17p' "$0" >&2
  exit 2
fi
build=$1 data=$2 work=$3 out=$4
fit_variant=${FIT_VARIANT:-default} synth_seed=${SYNTH_SEED:-1}
steps=${5:-1200}
shift $(($# < 5 ? $# : 5))
cases=("$@")
[ ${#cases[@]} -gt 0 ] || cases=(p_r1_y40 p_r1_y20 p_r2_y40 p_r2_y20 s_r1_y40 s_r1_y20 s_r2_y40 s_r2_y20)
lgn=$build/tools/lorgnette
for tool in "$lgn" "$build/benchmarks/nerf/bench_room_matte" "$build/benchmarks/fit/bench_fit_nerf"; do
  if [ ! -x "$tool" ]; then
    echo "room_matrix.sh: $tool is missing; build it first (cmake --build $build --target $(basename "$tool"))" >&2
    exit 2
  fi
done
# FIT_VARIANT is checked now, not after hours of training (bench_fit_nerf without cases checks its
# arguments and exits).
"$build/benchmarks/fit/bench_fit_nerf" "$out/fit" --variants "$fit_variant" || exit 2
scan=$data/heads/lee-perry-smith/LeePerrySmith.glb
mkdir -p "$work" "$out/fit"

matte_args=() fit_args=()
for c in "${cases[@]}"; do
  IFS=_ read -r who room arc <<<"$c"
  case $who in
    p) subject=(--procedural) ;;
    s) subject=(--mesh "$scan") ;;
    *) echo "unknown subject in case '$c' (p or s)" >&2 && exit 2 ;;
  esac
  case $arc in
    y40) arc_args=(--yaw-range -40 40 --pitch-range -10 10) ;;
    y20) arc_args=(--yaw-range -20 20 --pitch-range -15 15) ;;
    *) echo "unknown arc in case '$c' (y40 or y20)" >&2 && exit 2 ;;
  esac
  ds=$work/$c model=$work/$c.lnerf
  if [ ! -f "$ds/transforms.json" ]; then
    "$lgn" -q synth "${subject[@]}" --room "${room#r}" --views 40 --size 240x320 "${arc_args[@]}" --seed "$synth_seed" -o "$ds"
  fi
  if [ ! -f "$model" ]; then
    step_args=(--steps "$steps")
    [ "$steps" != default ] || step_args=()
    "$lgn" train "$ds" -o "$model" "${step_args[@]}" --seed "${SEED:-1337}" --background on ${TRAIN_ARGS:-} >"$work/$c.train.log" 2>&1
  fi
  grep -h "subject box\|subject region\|trained" "$work/$c.train.log" | sed "s/^/$c: /" >&2 || true
  matte_args+=(--case "$c" "$model" "$ds")
  fit_args+=(--case "$c" "$model" "$ds")
done

"$build/benchmarks/nerf/bench_room_matte" "$out" "${matte_args[@]}" --sheet-views 2
"$build/benchmarks/fit/bench_fit_nerf" "$out/fit" "${fit_args[@]}" --variants "$fit_variant" --repeats 1 --no-profile || true

# One row per case: the matte scores and the fit's errors (the fit's CSV may lack a case whose
# fit failed: its columns stay empty).
awk -F, -v variant="$fit_variant" 'NR == FNR { if (FNR > 1 && $2 == variant) fit[$1] = $4 "," $5 "," $6 "," $7 "," $NF; next }
         FNR == 1 { print $0 ",nose_mm,ear_l_mm,ear_r_mm,rotation_deg,fit_status"; next }
         { f = ($1 in fit) ? fit[$1] : ",,,,no fit row"; print $0 "," f }' \
  "$out/fit/fit_nerf.csv" "$out/room_matte.csv" >"$out/room_matrix.csv"
column -s, -t <"$out/room_matrix.csv"
