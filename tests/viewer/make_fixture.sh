#!/usr/bin/env bash
# The viewer tests' shared fixture: a tiny trained head (procedural head, 24 views of 64x64, 400
# steps of 2^14 samples: about 5 s on 2 cores) and a catalogue of two parametric frames, the first
# fitted by `lorgnette fit` (about 25 s) so it has a placement beside it and the second not.
# Usage: make_fixture.sh LORGNETTE DIR. Kept between runs while this script is unchanged and the
# current binary still renders the model (a snapshot format change makes it rebuild).
set -euo pipefail
L="$1"
DIR="$2"
STAMP="$(cksum < "$0")"
if [ -f "$DIR/.complete" ] && [ "$(cat "$DIR/.complete")" = "$STAMP" ] &&
   "$L" -q render "$DIR/head.lnerf" --orbit 1 --size 16x16 --no-video --force -o "$DIR/check" > /dev/null 2>&1; then
  echo "viewer fixture up to date: $DIR"
  exit 0
fi
rm -rf "$DIR"
mkdir -p "$DIR/catalogue"
"$L" -q synth --procedural -o "$DIR/dataset" --views 24 --size 64x64
"$L" -q train "$DIR/dataset" -o "$DIR/head.lnerf" --steps 400 --batch-log2 14 --log2-table 14
"$L" -q glasses make --lens 52 --bridge 18 --temple 140 --shape round -o "$DIR/catalogue/a-round.glb" > /dev/null
"$L" -q glasses make --lens 50 --bridge 18 --temple 140 --shape rect -o "$DIR/catalogue/b-rect.glb" > /dev/null
"$L" -q fit "$DIR/head.lnerf" --glasses "$DIR/catalogue/a-round.glb" -o "$DIR/catalogue/a-round.glb.placement.json" --views 8
echo "$STAMP" > "$DIR/.complete"
echo "viewer fixture written: $DIR"
