#!/bin/sh
# tools/fuzz/run_fuzz.sh SECONDS [FORMAT...]
# Builds the libFuzzer harnesses with clang (ASan + UBSan) in build-fuzz/ and runs each
# for SECONDS (default 60), FORMAT in gltf glb json (default: all three, one after the
# other; FUZZ_PARALLEL=1 runs them at the same time). The working corpus starts from
# tools/fuzz/corpus/FORMAT and grows in build-fuzz/fuzz/corpus/FORMAT (the repository's
# seeds stay small); crashes, timeouts and OOMs land in build-fuzz/fuzz/artifacts/FORMAT.
# Exit status: 0 when no harness found anything. Env: ZZ_FUZZ_BUILD (build dir),
# ZZ_JOBS (build parallelism), FUZZ_ARGS (extra libFuzzer flags), ZZ_FUZZ_NO_TRACE=1 (load
# and check scenes but do not trace them).
set -eu

ROOT=$(cd "$(dirname "$0")/../.." && pwd)
SECONDS_EACH="${1:-60}"
[ $# -gt 0 ] && shift
FORMATS="${*:-gltf glb json}"
BUILD="${ZZ_FUZZ_BUILD:-$ROOT/build-fuzz}"
JOBS="${ZZ_JOBS:-2}"

command -v clang++ >/dev/null 2>&1 || { echo "run_fuzz: clang++ not found (apt-get install clang)" >&2; exit 2; }
if [ ! -f "$BUILD/build.ninja" ]; then
  CC=clang CXX=clang++ cmake -S "$ROOT" -B "$BUILD" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    -DZZ_BUILD_BENCH=ON >/dev/null
fi
targets=""
for f in $FORMATS; do targets="$targets fuzz_$f"; done
# shellcheck disable=SC2086
cmake --build "$BUILD" -j "$JOBS" --target $targets >/dev/null

run_one() {
  f=$1
  corpus="$BUILD/fuzz/corpus/$f"
  artifacts="$BUILD/fuzz/artifacts/$f"
  mkdir -p "$corpus" "$artifacts"
  log="$BUILD/fuzz/$f.log"
  status=0
  # shellcheck disable=SC2086
  "$BUILD/tools/fuzz/fuzz_$f" -max_total_time="$SECONDS_EACH" -timeout=10 -rss_limit_mb=2048 \
    -print_final_stats=1 -dict="$ROOT/tools/fuzz/scene.dict" -artifact_prefix="$artifacts/" \
    ${FUZZ_ARGS:-} "$corpus" "$ROOT/tools/fuzz/corpus/$f" >"$log" 2>&1 || status=$?
  execs=$(grep -ao 'stat::number_of_executed_units: *[0-9]*' "$log" | grep -o '[0-9]*$' || echo "?")
  found=$(find "$artifacts" -type f | wc -l)
  summary="fuzz_$f: ${SECONDS_EACH}s, $execs execs, exit $status, $found artifact(s) in $artifacts (log $log)"
  echo "$summary"
  echo "$(date -u +%FT%TZ) trace=$([ "${ZZ_FUZZ_NO_TRACE:-0}" = 1 ] && echo off || echo on) $summary" >>"$BUILD/fuzz/history.txt"
  [ "$status" = 0 ] && [ "$found" = 0 ] && return 0
  # Where the run's machine is gone afterwards (CI), what it found must be in its output:
  # the sanitizer's report and each input, base64, to replay with
  #   base64 -d > input && build-fuzz/tools/fuzz/fuzz_FORMAT input
  echo "fuzz_$f: its report:"
  report=$(grep -anE 'ERROR: |runtime error|BUG: |deadly signal' "$log" | head -n 1 | cut -d: -f1)
  if [ -n "$report" ]; then
    tail -n "+$report" "$log" | grep -av '^#[0-9]' | head -n 60 | cut -c1-300 | sed 's/^/  | /'
  else
    grep -av '^#[0-9]' "$log" | tail -n 20 | cut -c1-300 | sed 's/^/  | /'
  fi
  find "$artifacts" -type f | while read -r a; do
    echo "fuzz_$f: artifact $(basename "$a"), $(wc -c <"$a") bytes, base64:"
    head -c 65536 "$a" | base64 -w 100 | sed 's/^/  /'
  done
  return 1
}

failed=0
if [ "${FUZZ_PARALLEL:-0}" = 1 ]; then
  pids=""
  for f in $FORMATS; do
    ( run_one "$f" ) &
    pids="$pids $!"
  done
  for p in $pids; do wait "$p" || failed=1; done
else
  for f in $FORMATS; do run_one "$f" || failed=1; done
fi
exit $failed
