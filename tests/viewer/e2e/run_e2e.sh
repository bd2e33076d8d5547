#!/usr/bin/env bash
# End-to-end test of `lorgnette view` in headless Chromium (Debian `chromium`) driven by
# playwright-core from npm: starts the viewer on the fixture's head with a fresh copy of its
# catalogue, runs viewer_e2e.cjs against it, and keeps the screenshots in WORK/screens.
# Usage: run_e2e.sh LORGNETTE FIXTURE_DIR WORK_DIR. Exit 77 (ctest: skipped) when node, chromium or
# playwright-core cannot be had; LORGNETTE_CHROMIUM overrides the browser's path.
set -uo pipefail
L="$1"
FIXTURE="$2"
WORK="$3"
HERE="$(cd "$(dirname "$0")" && pwd)"
CHROMIUM="${LORGNETTE_CHROMIUM:-/usr/bin/chromium}"

skip() { echo "SKIP: $*"; exit 77; }
command -v node > /dev/null || skip "node is not installed (Debian: apt-get install nodejs npm)"
[ -x "$CHROMIUM" ] || skip "no Chromium at $CHROMIUM (Debian: apt-get install chromium; or set LORGNETTE_CHROMIUM)"
NODE_MAJOR="$(node -p 'process.versions.node.split(".")[0]')"
[ "$NODE_MAJOR" -ge 18 ] || skip "node $NODE_MAJOR is too old for playwright-core (needs 18+)"
[ -f "$FIXTURE/.complete" ] || { echo "FAIL: the viewer fixture is missing (ctest -R viewer_fixture)"; exit 1; }

mkdir -p "$WORK"
if [ ! -f "$WORK/node_modules/playwright-core/package.json" ]; then
  command -v npm > /dev/null || skip "npm is not installed (Debian: apt-get install npm)"
  echo "installing playwright-core into $WORK (npm)"
  (cd "$WORK" && npm install --no-audit --no-fund --no-save --loglevel=error playwright-core@1) ||
    skip "cannot install playwright-core from npm (offline?)"
fi

rm -rf "$WORK/catalogue" "$WORK/screens"
cp -r "$FIXTURE/catalogue" "$WORK/catalogue"
mkdir -p "$WORK/screens"
"$L" view "$FIXTURE/head.lnerf" --catalogue "$WORK/catalogue" --no-fit --port 0 --size 426x240 \
  > "$WORK/server.out" 2> "$WORK/server.err" &
SERVER=$!
trap 'kill "$SERVER" 2> /dev/null; wait "$SERVER" 2> /dev/null' EXIT
URL=""
for _ in $(seq 1 600); do
  URL="$(grep -o 'http://127.0.0.1:[0-9]*/' "$WORK/server.out" | head -1 || true)"
  [ -n "$URL" ] && break
  kill -0 "$SERVER" 2> /dev/null || { echo "FAIL: the viewer exited:"; cat "$WORK/server.err"; exit 1; }
  sleep 0.1
done
[ -n "$URL" ] || { echo "FAIL: the viewer printed no URL in 60 s"; cat "$WORK/server.err"; exit 1; }
echo "viewer at $URL"
node "$HERE/viewer_e2e.cjs" "$URL" "$WORK" "$CHROMIUM"
RC=$?
kill -0 "$SERVER" 2> /dev/null || { echo "FAIL: the viewer died during the test"; tail -20 "$WORK/server.err"; exit 1; }
echo "screenshots: $WORK/screens"
exit $RC
