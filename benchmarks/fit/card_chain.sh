#!/usr/bin/env bash
# True size with a card end to end through the README's commands (#44): a synthetic room capture with
# a card (`synth --procedural --room 1 --card`), `capture --card-only`, `train`, `glasses make` and
# `fit` (scale policy auto: true size from the card). Prints the card's scale error, PD against the
# head's pupils and the width verdict against the one the head's true face width gives.
#
#   benchmarks/fit/card_chain.sh BUILD_DIR OUT_DIR
# Environment: SEED (3), VIEWS (24), SIZE (320x320), YAW (50: the sweep is -YAW..YAW), STEPS (1500).
set -euo pipefail
build=${1:?usage: card_chain.sh BUILD_DIR OUT_DIR}
out=${2:?usage: card_chain.sh BUILD_DIR OUT_DIR}
cli=$build/tools/lorgnette
[ -x "$cli" ] || { echo "card_chain.sh: $cli is not built" >&2; exit 1; }
mkdir -p "$out"
cd "$out"
yaw=${YAW:-50}
"$cli" -q synth --procedural --room 1 --card --seed "${SEED:-3}" --yaw-range "-$yaw" "$yaw" \
  --views "${VIEWS:-24}" --size "${SIZE:-320x320}" -o cap --force
"$cli" capture --card-only cap --json >card.json
"$cli" -q train cap -o head.lnerf --steps "${STEPS:-1500}" --seed 1 --force
"$cli" -q glasses make --lens 52 --bridge 18 --temple 140 -o frame.glb --force >/dev/null
"$cli" fit head.lnerf --glasses frame.glb -o placement.json --force >fit.log 2>&1
python3 - <<'PY'
import json
gt = json.load(open("cap/ground_truth.json"))
card = json.load(open("card.json"))
p = json.load(open("placement.json"))
print(f"card: {card.get('mm_per_unit', 0):.3f} mm per dataset unit, true {gt['mm_per_unit']:.3f} "
      f"({100 * (card.get('mm_per_unit', 0) / gt['mm_per_unit'] - 1):+.2f} %), {card.get('frames', 0)} frames")
print(f"fit: scale_source {p.get('scale_source')}, policy {p.get('scale_policy')}, "
      f"PD {p['pd_mm']:.2f} +- {p.get('pd_uncertainty_mm', 0):.2f} mm, true {gt['pd_mm']:.2f} "
      f"({p['pd_mm'] - gt['pd_mm']:+.2f} mm)")
for r in p.get("advice", {}).get("rules", []):
    line = f"  {r['name']}: {r['verdict']} (frame {r.get('frame_mm', 0):.1f}, head {r.get('head_mm', 0):.1f})"
    if r["name"] == "frame_width":
        d = r.get("frame_mm", 0) - gt["face_width_temples_mm"]
        truth = "good" if -5 <= d <= 5 else ("too narrow" if d < -5 else "too wide")
        line += f"; true face width {gt['face_width_temples_mm']:.1f}: {truth}"
    print(line)
PY
