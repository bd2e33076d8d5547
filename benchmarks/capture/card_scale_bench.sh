#!/usr/bin/env bash
# The card scale on synthetic room captures (issue #44): `lorgnette synth --room R --card` over head
# sizes, seeds, both textured rooms and two sweep arcs, then `lorgnette capture --card-only` on each.
# Writes one CSV row per capture: the true and measured millimetres per unit, the error in percent,
# the stated uncertainty, the frames used, and the card step's seconds (its extra cost in `capture`).
# Usage: benchmarks/capture/card_scale_bench.sh [LORGNETTE_BINARY] [OUT_CSV] [SIZE]
set -euo pipefail
bin=${1:-build/tools/lorgnette}
out=${2:-card_scale.csv}
size=${3:-384x384}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
echo "room,seed,head_scale,yaw_range,true_mm_per_unit,card_mm_per_unit,error_percent,uncertainty,frames,card_seconds,message" >"$out"
# room seed head_scale yaw_min yaw_max
runs=(
  "1 1 0.90 -35 35" "2 2 1.10 -35 35" "1 3 1.00 -50 50" "2 4 0.88 -50 50"
  "1 5 1.12 -35 35" "2 6 1.00 -35 35" "1 7 0.95 -50 50" "2 8 1.05 -50 50"
)
for r in "${runs[@]}"; do
  read -r room seed scale y0 y1 <<<"$r"
  d="$work/r${room}_s${seed}"
  "$bin" synth --procedural --room "$room" --card --seed "$seed" --head-scale "$scale" \
    --yaw-range "$y0" "$y1" --views 24 --size "$size" --samples 2 -o "$d" >/dev/null 2>&1
  "$bin" capture --card-only "$d" --json 2>/dev/null >"$d/card.json"
  python3 - "$d" "$room" "$seed" "$scale" "$y0..$y1" >>"$out" <<'PY'
import json, sys
d, room, seed, scale, arc = sys.argv[1:]
truth = json.load(open(d + "/ground_truth.json"))["mm_per_unit"]
c = json.load(open(d + "/card.json"))
m = c.get("mm_per_unit")
err = "" if m is None else f"{100 * (m / truth - 1):.3f}"
msg = c["message"].replace(",", ";").replace('"', "'")
print(f"{room},{seed},{scale},{arc},{truth},{m or ''},{err},{c.get('mm_per_unit_uncertainty', '')},"
      f"{c.get('frames', 0)},{c['seconds']:.3f},\"{msg}\"")
PY
  tail -1 "$out"
done
