#!/usr/bin/env bash
# Builds the libFuzzer harnesses (the `fuzz` preset: clang, ASan + UBSan) and runs each for SECONDS over a scratch
# copy of its seed corpus (tests/fuzz/corpus/<harness>/, left clean), then prints a table of executions, executions
# per second and findings. Exits non-zero on any finding: a crash, a sanitizer report, an input that runs past
# -timeout, an allocation past -malloc_limit_mb, a leak. Findings are kept under build-fuzz/findings/.
#   scripts/fuzz.sh [SECONDS_PER_HARNESS] [HARNESS...]     (default 10 s, every harness; names as in tests/fuzz)
# FUZZ_PARALLEL=N runs N harnesses at once (one libFuzzer process each); FUZZ_KEEP=1 keeps the grown corpora.
set -euo pipefail
cd "$(dirname "$0")/.."
seconds="${1:-10}"
shift || true
[[ "$seconds" =~ ^[0-9]+$ ]] || { echo "usage: scripts/fuzz.sh [SECONDS_PER_HARNESS] [HARNESS...]" >&2; exit 2; }

# Quiet when it builds; the build's own output when it does not, so that a failure names its cause.
mkdir -p build-fuzz
if ! { cmake --preset fuzz && cmake --build --preset fuzz; } >build-fuzz/fuzz-build.log 2>&1; then
  tail -40 build-fuzz/fuzz-build.log >&2
  echo "fuzz.sh: building the harnesses failed (whole log: build-fuzz/fuzz-build.log)" >&2
  exit 1
fi

all=()
for src in tests/fuzz/fuzz_*.cpp; do all+=("$(basename "$src" .cpp | sed 's/^fuzz_//')"); done
harnesses=("${@:-${all[@]}}")
for h in "${harnesses[@]}"; do
  [ -x "build-fuzz/tests/fuzz/fuzz_$h" ] || { echo "fuzz.sh: no harness \"$h\" (have: ${all[*]})" >&2; exit 2; }
done

scratch="$(mktemp -d "${TMPDIR:-/tmp}/sva-fuzz.XXXXXX")"
findings="build-fuzz/findings"
mkdir -p "$findings"
[ "${FUZZ_KEEP:-0}" = 1 ] || trap 'rm -rf "$scratch"' EXIT

run_one() {  # harness -> scratch/<h>.log, scratch/<h>.rc
  local h="$1" work="$scratch/$1"
  mkdir -p "$work/corpus" "$work/artifacts"
  cp -r "tests/fuzz/corpus/$h/." "$work/corpus/" 2>/dev/null || true
  local max_len=16384
  case "$h" in mesh | dataset | recording) max_len=65536 ;; esac
  set +e
  ASAN_OPTIONS="${ASAN_OPTIONS:-detect_leaks=1}" UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1" \
    "build-fuzz/tests/fuzz/fuzz_$h" "$work/corpus" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2560 \
    -malloc_limit_mb=2048 -max_len="$max_len" -print_final_stats=1 -artifact_prefix="$work/artifacts/" \
    >"$scratch/$h.log" 2>&1
  echo $? >"$scratch/$h.rc"
  set -e
}

parallel="${FUZZ_PARALLEL:-1}"
for h in "${harnesses[@]}"; do
  while [ "$(jobs -rp | wc -l)" -ge "$parallel" ]; do sleep 0.2; done
  run_one "$h" &
done
wait

status=0
printf "%-16s %14s %10s %9s %8s %8s\n" harness executions exec/s corpus peak_MB findings
for h in "${harnesses[@]}"; do
  log="$scratch/$h.log"
  execs=$(grep -o 'stat::number_of_executed_units: [0-9]*' "$log" | tail -1 | awk '{print $2}')
  rate=$(grep -o 'stat::average_exec_per_sec: *[0-9]*' "$log" | tail -1 | awk '{print $2}')
  peak=$(grep -o 'stat::peak_rss_mb: *[0-9]*' "$log" | tail -1 | awk '{print $2}')
  corpus=$(find "$scratch/$h/corpus" -type f | wc -l)
  found=$(find "$scratch/$h/artifacts" -type f | wc -l)
  rc=$(cat "$scratch/$h.rc")
  if [ "$rc" != 0 ] || [ "$found" != 0 ]; then
    status=1
    found=$((found > 0 ? found : 1))
    cp "$log" "$findings/$h.log"
    cp "$scratch/$h/artifacts/"* "$findings/" 2>/dev/null || true
  fi
  printf '%-16s %14s %10s %9s %8s %8s\n' "$h" "${execs:-?}" "${rate:-?}" "$corpus" "${peak:-?}" "$found"
done
if [ "$status" != 0 ]; then
  echo "fuzz.sh: FINDINGS: logs and inputs in $findings/ (reproduce: build-fuzz/tests/fuzz/fuzz_HARNESS INPUT)" >&2
fi
[ "${FUZZ_KEEP:-0}" = 1 ] && echo "fuzz.sh: grown corpora kept in $scratch" >&2
exit "$status"
