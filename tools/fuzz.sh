#!/usr/bin/env bash
# Fuzzes the file parsers with libFuzzer (clang, ASan + UBSan): transforms.json, .lnerf snapshots
# (the whole file, and the JSON header alone), COLMAP text and binary models, placement.json, the
# glasses loader and the reference-point sidecar (the targets: fuzz/).
# Usage: tools/fuzz.sh [SECONDS_PER_TARGET]   (default 30; tools/test.sh, the CI run, uses 10)
# Environment: FUZZ_REPORT (default docs/bench/fuzz.md) is where the results go;
# FUZZ_SLOW_IS_FATAL=0 reports inputs that time out or run out of memory without failing (the test
# command's short run, on a machine whose load makes timeouts a matter of chance); likewise
# FUZZ_THIRD_PARTY_IS_FATAL=0 for a crash whose sanitizer summary lies inside Debian's libassimp
# (Assimp's importers: ours to work around, not to fix, and found only by chance in a short run).
# Any other crash always fails.
#
# Builds only the fuzz targets in build-fuzz/ (a unity build, at -O1 with the line tables that
# fuzz/CMakeLists.txt asks for: 268 -> 154 s on 2 cores against one file at a time with full debug
# information), starts each from the generated seeds, the committed regression inputs and the corpus
# of earlier runs (build-fuzz/corpus/<target>/), and writes docs/bench/fuzz.md: per target the
# seconds, executions, final corpus and coverage, and what was found. Exits non-zero when a target
# crashes, naming the input that did it.
set -euo pipefail
cd "$(dirname "$0")/.."
seconds="${1:-30}"
report="${FUZZ_REPORT:-docs/bench/fuzz.md}"
slow_is_fatal="${FUZZ_SLOW_IS_FATAL:-1}"
third_party_is_fatal="${FUZZ_THIRD_PARTY_IS_FATAL:-1}"
if ! [[ "$seconds" =~ ^[0-9]+$ ]] || [ "$seconds" -lt 1 ]; then
  echo "usage: tools/fuzz.sh [SECONDS_PER_TARGET]  (a whole number of seconds, default 30)" >&2
  exit 2
fi
targets=(transforms snapshot snapshot_header colmap_text colmap_binary placement glasses refpoints)
out=build-fuzz
if ! command -v clang++ >/dev/null || [ ! -e "$(clang++ -print-file-name=libclang_rt.fuzzer-x86_64.a)" ]; then
  echo "tools/fuzz.sh needs clang with libFuzzer: apt-get install clang libclang-rt-dev" >&2
  exit 2
fi

cmake -S . -B "$out" -G Ninja -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ \
  -DCMAKE_BUILD_TYPE=Debug -DCMAKE_CXX_FLAGS_DEBUG=-O1 -DCMAKE_C_FLAGS_DEBUG=-O1 \
  -DLORGNETTE_BUILD_FUZZERS=ON -DLORGNETTE_BUILD_TESTS=OFF -DLORGNETTE_BUILD_BENCHMARKS=OFF \
  -DCMAKE_UNITY_BUILD=ON >/dev/null
cmake --build "$out" -j "$(nproc)" --target lorgnette_fuzzers
"$out/fuzz/fuzz_make_seeds" "$out/seeds" >/dev/null

# "#123 DONE cov: 456 ft: 789 corp: 12/3456b ..." -> the value after `key`.
stat_of() { sed -n "s/.* $2: \([0-9]*\).*/\1/p" <<<"$1"; }

# Assimp leaks on some malformed files; that is its bug, so only leaks outside it are reported.
export LSAN_OPTIONS="suppressions=$PWD/fuzz/lsan.supp:print_suppressions=0${LSAN_OPTIONS:+:$LSAN_OPTIONS}"

# Runs one target for `seconds`; its exit status goes to logs/<target>.rc.
fuzz_target() {
  local t="$1" corpus="$out/corpus/$1" crashes="$out/crashes/$1" log="$out/logs/$1.log"
  local args=("$corpus" "$out/seeds/$t")  # the first folder collects the new inputs
  [ -d "fuzz/regressions/$t" ] && args+=("fuzz/regressions/$t")
  [ -f "fuzz/dicts/$t.dict" ] && args+=("-dict=fuzz/dicts/$t.dict")
  local rc=0
  "$out/fuzz/${t}_fuzz" "${args[@]}" \
    -max_total_time="$seconds" -rss_limit_mb=2048 -timeout=10 -print_final_stats=1 \
    -artifact_prefix="$crashes/" >"$log" 2>&1 || rc=$?
  echo "$rc" >"$out/logs/$t.rc"
}

# One target per core at a time (each fuzzer is one process on one core): the same fuzzing time
# per target in a fraction of the wall time.
at_once=$(nproc)
for ((i = 0; i < ${#targets[@]}; i += at_once)); do
  for t in "${targets[@]:i:at_once}"; do
    mkdir -p "$out/corpus/$t" "$out/crashes/$t" "$out/logs"
    echo "fuzzing $t for $seconds s (log: $out/logs/$t.log)"
    fuzz_target "$t" &
  done
  wait
done

rows=() findings=() failed=0
for t in "${targets[@]}"; do
  corpus="$out/corpus/$t" log="$out/logs/$t.log"
  rc=$(cat "$out/logs/$t.rc")
  last=$(grep -E '^#[0-9]+[[:space:]]+(DONE|NEW|REDUCE|pulse|INITED)' "$log" | tail -1 || true)
  runs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)
  cov=$(stat_of "$last" cov)
  files=$(find "$corpus" -type f | wc -l)
  if [ "$rc" -eq 0 ]; then
    found="nothing"
  elif [ "$slow_is_fatal" = 0 ] && grep -qE 'ERROR: libFuzzer: (timeout|out-of-memory)' "$log"; then
    artifact=$(sed -n 's/.*Test unit written to \(.*\)$/\1/p' "$log" | tail -1)
    what=$(grep -m1 -E 'ERROR: libFuzzer: (timeout|out-of-memory)' "$log")
    found="slow input (not fatal here): ${what} — input \`${artifact:-none written}\`"
    echo "fuzz: $t: slow input, reported and not fatal in this run: $what (${artifact:-none written})"
  elif [ "$third_party_is_fatal" = 0 ] && grep -qE '^SUMMARY: [A-Za-z]+Sanitizer: .*\(/(usr/)?lib/x86_64-linux-gnu/libassimp' "$log"; then
    artifact=$(sed -n 's/.*Test unit written to \(.*\)$/\1/p' "$log" | tail -1)
    what=$(grep -m1 -E '^SUMMARY: ' "$log")
    found="crash inside a Debian library (not fatal here): ${what} — input \`${artifact:-none written}\`"
    echo "fuzz: $t: crash inside a system library, reported and not fatal in this run: $what (${artifact:-none written})"
  else
    failed=1
    artifact=$(sed -n 's/.*Test unit written to \(.*\)$/\1/p' "$log" | tail -1)
    what=$(grep -m1 -E '^SUMMARY: |fuzz invariant failed|ERROR: libFuzzer' "$log" || echo "exit status $rc")
    found="**crash**: ${what} — input \`${artifact:-none written}\`"
    findings+=("$t: $what; input: ${artifact:-none written}; log: $log")
  fi
  rows+=("| $t | $seconds | ${runs:-?} | $files | ${cov:-?} | $found |")
done

regressions=$(find fuzz/regressions -type f 2>/dev/null | sort | sed 's|^fuzz/regressions/|- `|; s|$|`|')
{
  echo "# Fuzzing the file parsers"
  echo
  echo "\`tools/fuzz.sh $seconds\` on $(date -u +%Y-%m-%d), commit $(git rev-parse --short HEAD 2>/dev/null || echo '?'),"
  echo "$(clang++ --version | head -1), libFuzzer with ASan + UBSan, $(nproc) cores, one target per core at a time."
  echo "Each run starts from the generated seeds (\`fuzz_make_seeds\`), the regression inputs in"
  echo "\`fuzz/regressions/<target>/\` and the corpus earlier runs left in \`build-fuzz/corpus/<target>/\`."
  echo "Corpus: the files in that folder after the run; cov: libFuzzer's covered edges at the end."
  echo "Leaks inside Assimp are not reported (\`fuzz/lsan.supp\`); Assimp itself is not instrumented."
  echo
  echo "| target | seconds | executions | corpus files | cov | found |"
  echo "|---|---:|---:|---:|---:|---|"
  printf '%s\n' "${rows[@]}"
  echo
  echo "Inputs that crashed a parser before its fix, replayed by \`ctest -L fuzz\` in the normal build:"
  echo
  echo "${regressions:-none}"
} >"$report"
echo "wrote $report"

if [ "$failed" -ne 0 ]; then
  echo "FUZZING FOUND CRASHES:" >&2
  printf '  %s\n' "${findings[@]}" >&2
  echo "Fix the parser, then keep the input as fuzz/regressions/<target>/<what-it-does> (ctest -L fuzz replays it)." >&2
  exit 1
fi
