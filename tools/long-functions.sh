#!/usr/bin/env bash
# Lists the library functions longer than a limit (default 80 lines, the house limit), longest first:
# "lines path:line name". Library folders only (tests/, benchmarks/, fuzz/ hold no library code).
# Lambdas count inside the function that holds them. Needs Universal Ctags (Debian: universal-ctags).
# Usage: tools/long-functions.sh [LIMIT] [FOLDER...]
set -euo pipefail
cd "$(dirname "$0")/.."
limit=${1:-80}
shift || true
folders=("$@")
[ ${#folders[@]} -gt 0 ] || folders=(capture demo fit host kernels mesh python/src synth tools viewer)
find "${folders[@]}" -name '*.cpp' -o -name '*.h' -o -name '*.cl' | sort |
  ctags -L - --output-format=json --fields=+ne --kinds-C++=f --kinds-C=f --language-force=C++ -o - 2>/dev/null |
  python3 -c '
import json, sys
limit = int(sys.argv[1])
rows = []
for line in sys.stdin:
    t = json.loads(line)
    if t.get("_type") != "tag" or t["name"].startswith("__anon") or "end" not in t:
        continue
    n = t["end"] - t["line"] + 1
    if n > limit:
        rows.append((n, "%s:%d" % (t["path"], t["line"]), t.get("scope", "") + ("::" if t.get("scope") else "") + t["name"]))
for n, where, name in sorted(rows, key=lambda r: (-r[0], r[1])):
    print("%4d %s %s" % (n, where, name))
' "$limit"
