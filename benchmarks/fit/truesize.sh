#!/usr/bin/env bash
# The scale chain against synthetic ground truth (#44): for each seed, a procedural head (its size
# varies with the seed) filmed by `lorgnette synth`, a short training, then bench_truesize (the fit
# with its default settings; the irises' and the mean face's scale and PD against the head's exact
# ones) into one CSV. Extra synth arguments (a room, an arc: part A's captures) go in SYNTH_ARGS.
#
#   benchmarks/fit/truesize.sh BUILD_DIR OUT_DIR [SEED ...]     (default seeds: 1 2)
# Environment: STEPS (training steps, default 1500), VIEWS (default 32), SIZE (default 160x160),
# SYNTH_ARGS (appended to `lorgnette synth`). Each capture takes a few minutes on 2 CPU cores.
set -euo pipefail
build=${1:?usage: truesize.sh BUILD_DIR OUT_DIR [SEED ...]}
out=${2:?usage: truesize.sh BUILD_DIR OUT_DIR [SEED ...]}
shift 2
seeds=("$@")
[ ${#seeds[@]} -gt 0 ] || seeds=(1 2)
cli=$build/tools/lorgnette
bench=$build/benchmarks/fit/bench_truesize
for tool in "$cli" "$bench"; do
  [ -x "$tool" ] || { echo "truesize.sh: $tool is not built (cmake --build $build --target lorgnette bench_truesize)" >&2; exit 1; }
done
mkdir -p "$out"
frame=$out/frame-52-18-140.glb
[ -f "$frame" ] || "$cli" -q glasses make --lens 52 --bridge 18 --temple 140 -o "$frame"
pairs=()
for seed in "${seeds[@]}"; do
  ds=$out/head-$seed
  model=$out/head-$seed.lnerf
  if [ ! -f "$model" ]; then
    # shellcheck disable=SC2086  # SYNTH_ARGS is a list of words on purpose
    "$cli" -q synth --procedural --seed "$seed" --views "${VIEWS:-32}" --size "${SIZE:-160x160}" \
      -o "$ds" --force ${SYNTH_ARGS:-}
    "$cli" -q train "$ds" -o "$model" --steps "${STEPS:-1500}" --seed "$seed" --force
  fi
  pairs+=("$model" "$ds")
done
"$bench" "$frame" "$out/truesize.csv" "${pairs[@]}"
echo "wrote $out/truesize.csv"
