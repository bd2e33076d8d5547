#!/usr/bin/env bash
# The fit advice against synthetic ground truth (#44): plain procedural heads of several sizes
# (`synth --head-scale`, no room, with masks: the quickest to train), a catalogue of parametric
# frames whose total widths run from 82 to 138 mm in 4 mm steps (bridges 14-22 mm and temples
# 120-150 mm in turn, so the other rules see several verdicts too), and for each head bench_advice on
# the frames within +-15 mm of its face width at the temples. Writes OUT_DIR/advice.csv and the chart
# OUT_DIR/advice_width.png (bench_advice --chart).
#
#   benchmarks/fit/advice.sh BUILD_DIR OUT_DIR [HEAD_SCALE ...]     (default: 0.88 0.96 1.04 1.12)
# Environment: SCALE (truth: the head's exact scale, given to the fit as a card's; chain: the
# product's scale chain), SOURCE (nerf: the trained model; mesh: the head's exact mesh), STEPS (default 1200), BATCH_LOG2 (16), VIEWS (32), SIZE (192x192).
set -euo pipefail
build=${1:?usage: advice.sh BUILD_DIR OUT_DIR [HEAD_SCALE ...]}
out=${2:?usage: advice.sh BUILD_DIR OUT_DIR [HEAD_SCALE ...]}
shift 2
scales=("$@")
[ ${#scales[@]} -gt 0 ] || scales=(0.88 0.96 1.04 1.12)
cli=$build/tools/lorgnette
bench=$build/benchmarks/fit/bench_advice
for tool in "$cli" "$bench"; do
  [ -x "$tool" ] || { echo "advice.sh: $tool is not built (cmake --build $build --target lorgnette bench_advice)" >&2; exit 1; }
done
mkdir -p "$out/frames"
# Total width = 2 lens + bridge + 5.9 mm (the parametric rect frame's two 3 mm rims, less overlap).
frames=()
for i in $(seq 0 14); do
  width=$((82 + 4 * i))
  bridge=$((14 + 2 * (i % 5)))
  while awk -v w="$width" -v b="$bridge" 'BEGIN { exit !((w - b - 5.9) / 2 < 30) }'; do bridge=$((bridge - 2)); done
  lens=$(awk -v w="$width" -v b="$bridge" 'BEGIN { printf "%.2f", (w - b - 5.9) / 2 }')
  temple=$((120 + 10 * (i % 4)))
  f=$out/frames/w$width-b$bridge-t$temple.glb
  [ -f "$f" ] || "$cli" -q glasses make --lens "$lens" --bridge "$bridge" --temple "$temple" -o "$f"
  frames+=("$f")
done
parts=()
for s in "${scales[@]}"; do
  ds=$out/head-$s
  model=$out/head-$s.lnerf
  if [ ! -f "$model" ]; then
    "$cli" -q synth --procedural --seed 0 --head-scale "$s" --views "${VIEWS:-32}" --size "${SIZE:-192x192}" \
      --yaw-range -135 135 -o "$ds" --force
    "$cli" -q train "$ds" -o "$model" --steps "${STEPS:-1200}" --batch-log2 "${BATCH_LOG2:-16}" --seed 1 --force
  fi
  face=$(python3 -c "import json; print(json.load(open('$ds/ground_truth.json'))['face_width_temples_mm'])")
  mine=()
  for f in "${frames[@]}"; do
    w=$(basename "$f" | sed 's/^w\([0-9]*\)-.*/\1/')
    awk -v w="$w" -v f="$face" 'BEGIN { exit !(w >= f - 15 && w <= f + 15) }' && mine+=("$f")
  done
  "$bench" "$out/advice-$s.csv" "${SCALE:-truth}" "${SOURCE:-nerf}" "$model" "$ds" "${mine[@]}"
  parts+=("$out/advice-$s.csv")
done
{ head -n 1 "${parts[0]}"; for p in "${parts[@]}"; do tail -n +2 "$p"; done; } > "$out/advice.csv"
"$bench" --chart "$out/advice.csv" "$out/advice_width.png"
echo "wrote $out/advice.csv and $out/advice_width.png"
