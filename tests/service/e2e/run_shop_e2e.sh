#!/usr/bin/env bash
# The shopper's pages end to end in headless Chromium (Debian `chromium`) driven by playwright-core
# from npm: a synthetic head turn in a room (`synth --room`, 24 views at 256x192) is encoded as an
# MP4, `lorgnette serve` runs with a one-frame catalogue at a tiny budget, and shop_e2e.cjs uploads
# the video on the upload page, follows the status page and checks the try-on page's pixels.
# Usage: run_shop_e2e.sh LORGNETTE WORK_DIR. Exit 77 (ctest: skipped) when node, chromium, ffmpeg,
# colmap or playwright-core cannot be had; LORGNETTE_CHROMIUM overrides the browser's path.
set -uo pipefail
L="$1"
WORK="$2"
HERE="$(cd "$(dirname "$0")" && pwd)"
CHROMIUM="${LORGNETTE_CHROMIUM:-/usr/bin/chromium}"

skip() { echo "SKIP: $*"; exit 77; }
fail() { echo "FAIL: $*"; exit 1; }
command -v node > /dev/null || skip "node is not installed (Debian: apt-get install nodejs npm)"
[ -x "$CHROMIUM" ] || skip "no Chromium at $CHROMIUM (Debian: apt-get install chromium; or set LORGNETTE_CHROMIUM)"
[ -x /usr/bin/ffmpeg ] && [ -x /usr/bin/colmap ] || skip "needs ffmpeg and colmap (tools/setup-debian.sh)"
NODE_MAJOR="$(node -p 'process.versions.node.split(".")[0]')"
[ "$NODE_MAJOR" -ge 18 ] || skip "node $NODE_MAJOR is too old for playwright-core (needs 18+)"

mkdir -p "$WORK"
if [ ! -f "$WORK/node_modules/playwright-core/package.json" ]; then
  command -v npm > /dev/null || skip "npm is not installed (Debian: apt-get install npm)"
  echo "installing playwright-core into $WORK (npm)"
  (cd "$WORK" && npm install --no-audit --no-fund --no-save --loglevel=error playwright-core@1) ||
    skip "cannot install playwright-core from npm (offline?)"
fi

rm -rf "$WORK/room" "$WORK/data" "$WORK/catalogue" "$WORK/screens" "$WORK/room.mp4"
mkdir -p "$WORK/data" "$WORK/catalogue" "$WORK/screens"
"$L" -q synth --procedural --room 1 --views 24 --size 256x192 --samples 1 -o "$WORK/room" > "$WORK/synth.log" 2>&1 ||
  fail "synth: $(tail -5 "$WORK/synth.log")"
/usr/bin/ffmpeg -loglevel error -framerate 8 -i "$WORK/room/images/%04d.png" -c:v libx264 -pix_fmt yuv420p \
  "$WORK/room.mp4" || fail "ffmpeg could not encode the video"
"$L" -q glasses make --lens 52 --bridge 18 --temple 140 --shape round -o "$WORK/catalogue/round.glb" > /dev/null ||
  fail "glasses make"

"$L" serve --data "$WORK/data" --catalogue "$WORK/catalogue" --port 0 --port-file "$WORK/data/port" \
  --capture-fps 8 --capture-max-side 256 --train-steps 400 --train-batch-log2 14 --fit-views 8 \
  --tryon-views 3 --tryon-size 192 > "$WORK/serve.log" 2>&1 &
SERVER=$!
trap 'kill "$SERVER" 2> /dev/null; wait "$SERVER" 2> /dev/null' EXIT
for _ in $(seq 1 600); do
  [ -s "$WORK/data/port" ] && break
  kill -0 "$SERVER" 2> /dev/null || fail "serve exited: $(tail -5 "$WORK/serve.log")"
  sleep 0.1
done
[ -s "$WORK/data/port" ] || fail "serve wrote no port in 60 s"
URL="http://127.0.0.1:$(cat "$WORK/data/port" | tr -d '\n')/"
echo "serving at $URL"
node "$HERE/shop_e2e.cjs" "$URL" "$WORK" "$CHROMIUM" "$WORK/room.mp4"
RC=$?
kill -0 "$SERVER" 2> /dev/null || { echo "FAIL: serve died during the test"; tail -20 "$WORK/serve.log"; exit 1; }
# The capture's token travels in the URL fragment and the Authorization header only: never logged.
TOKEN="$(cat "$WORK/token" 2> /dev/null)"
if [ -n "$TOKEN" ] && grep -rqF "$TOKEN" "$WORK/serve.log" "$WORK/data/captures"; then
  echo "not ok - the capture's token appears in the server's log or folder"
  RC=1
else
  echo "ok - the token is in no log"
fi
echo "screenshots: $WORK/screens"
exit $RC
