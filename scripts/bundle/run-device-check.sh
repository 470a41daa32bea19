#!/usr/bin/env bash
# The whole device check of a GPU loan in one call, from a bundle (scripts/bundle.sh), inside a time budget:
#   1. the device and the machine (device.txt);
#   2. the agreement tests first, whose printed lines locate a disagreement with the CPU reference (agreement.txt);
#   3. the whole test suite, areas in parallel, while paper3d is simulated and its map trained (suite.txt);
#   4. issue 52's goals first, so that a loan cut short still measures them: sva bench on paper3d, the Vulkan backend
#      one session at a time (10, 30, 100 readings, 3 trials), the same with light estimates (a robot's touch without
#      the host's fits: the touch goal as restated), the CPU reference on the same machine (bench-cpu.txt), then 64
#      per submission (10 and 30 readings) with full and with light estimates (the batch goal as restated); one
#      session's estimate on every thread beside the model of its critical path (estimate-span.txt:
#      bench/estimate_speed, 30 and 100 readings), one session's update under the span probe (update-span.txt), 64
#      sessions to 10 readings on 16 and 2 threads beside the model of their critical path (batch-span.txt:
#      bench/batch_speed); on a host of 16 cores or more (a GPU machine) the CPU reference's one session on 8 and 16
#      threads;
#   5. the diagnostics: 3 hypotheses per estimate as sva recognize asks (10 and 30 readings: the modes' path), the same
#      with a pose prior, the batch with a likelihood cut-off of 0.2 (fewer votes), with its tables warm (as a long
#      study's later groups find them), then to 10 readings untimed, the sessions' passes side by side and one at a
#      time (SVA_VK_SERIAL=1); on a host of 16 cores or more 256 sessions per submission (the two groups in flight
#      together that Engine::sessions_per_submission gives an 80-141 GB GPU at the default bound, 105-186 each) and
#      sva recognize of 512 sessions with one group in flight and with two (the double buffering), wall times and
#      whether the results are the same bytes (recognize-in-flight.txt). Each cut at the budget's end.
# The per-test logs and the benchmarks' JSON go into details.tgz: 18 files in all, 22 on a host of 16 cores.
#
#   run-device-check.sh OUT_DIR [SECONDS]    SECONDS: the budget for all of it (default 480)
# Environment: VK_DRIVER_FILES (the caller's ICD, kept), WORK (paper3d's data and map, default OUT_DIR/paper3d:
#   kept, so a second call skips the simulation), SIM_ARGS (extra `sva simulate` options, e.g. "--train 100
#   --test 20" for a quick small dataset), AREAS (the suite's areas, default all: tests/sva_tests_<area>),
#   ARCHIVE (a file: every file of OUT_DIR in one gzip'd tar too, written last, for a loan's tool that brings back
#   only a few files: the seventh GPU run lost all but 8 of its 17 files; docs/vulkan-backend.md).
# Prints a summary; exits 1 when a test failed, the agreement tests found no Vulkan device, or a benchmark failed or
# could not run; 2 on bad usage.
set -uo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/env.sh"
[[ $# -ge 1 && $# -le 2 && -n $1 ]] || { echo "usage: run-device-check.sh OUT_DIR [SECONDS]" >&2; exit 2; }
out=$1 budget=${2:-480}
[[ $budget =~ ^[0-9]+$ && $budget -ge 60 ]] || { echo "run-device-check: SECONDS must be a whole number >= 60, not '$budget'" >&2; exit 2; }
mkdir -p "$out" || exit 2
out=$(cd "$out" && pwd)
work=${WORK:-$out/paper3d}
t0=$SECONDS
left() { echo $((budget - (SECONDS - t0))); }
say() { echo "== $* ($((SECONDS - t0)) s)"; }

# Each driver file the caller named: present, its library found, and what that library cannot load (a bare NVIDIA
# container's driver without libglvnd left the first call of the fifth GPU run with no Vulkan test run).
driver_diagnosis() {
  local f lib
  local files=${VK_DRIVER_FILES:-}
  for f in ${files//:/ }; do
    [[ -f $f ]] || { echo "driver file $f: missing"; continue; }
    lib=$(sed -n 's/.*"library_path" *: *"\([^"]*\)".*/\1/p' "$f" | head -n 1)
    [[ $lib == /* || -z $lib ]] || lib=$(sva_system_lib "$lib")
    echo "driver file $f: library ${lib:-not found}"
    [[ -n $lib ]] && ldd "$lib" | grep 'not found' | sed 's/^/  cannot load: /'
  done
  return 0
}

say "device"
{
  date -u
  command -v nvidia-smi >/dev/null && nvidia-smi --query-gpu=name,driver_version,memory.total --format=csv
  echo "cores: $(nproc)"; grep -m1 'model name' /proc/cpuinfo
  echo "VK_DRIVER_FILES=${VK_DRIVER_FILES:-(loader default)}"
  "$BUNDLE/sva" --version
  driver_diagnosis
} >"$out/device.txt" 2>&1
cat "$out/device.txt"

say "agreement with the CPU reference"
LOG_DIR=$out/.agreement timeout $(($(left) / 4)) "$BUNDLE/run-tests.sh" 'vulkan:*bin by bin*' \
  'vulkan:*each key alone*' 'vulkan:the vote math*' "vulkan:the belief's integer math*" >"$out/agreement.txt" 2>&1
grep -h -A4 'warning' "$out"/.agreement/*.log >>"$out/agreement.txt" 2>/dev/null
grep -E 'passed,|FAILED|warning' -A3 "$out/agreement.txt" | head -40
# Skipped agreement tests mean no Vulkan device was found: the check has checked nothing, so it fails.
agreement_failed=0
read -r _ _ _ _ skipped _ < <(grep -E '^[0-9]+ passed, [0-9]+ failed, [0-9]+ skipped' "$out/agreement.txt" | tail -n 1)
if [[ ${skipped:-0} != 0 ]]; then
  echo "no Vulkan device: the agreement tests were skipped (device.txt says which driver was tried)" | tee -a "$out/agreement.txt"
  agreement_failed=1
fi

say "the whole suite, areas in parallel; paper3d simulated and trained meanwhile"
mkdir -p "$out/.suite"
export TEST_TIMEOUT=$(($(left) / 2))
read -r -a areas <<<"${AREAS:-}"
if [[ ${#areas[@]} -eq 0 ]]; then
  for exe in "$BUNDLE"/tests/sva_tests_*; do areas+=("${exe##*/sva_tests_}"); done
fi
for a in "${areas[@]}"; do
  (LOG_DIR=$out/.suite/$a timeout $(($(left) / 2)) "$BUNDLE/run-tests.sh" "$a" >"$out/.suite/$a.out" 2>&1) &
done
mkdir -p "$work"
if [[ ! -f $work/map.svam ]]; then
  # shellcheck disable=SC2086  # SIM_ARGS is a list of options
  "$BUNDLE/sva" --quiet simulate --scene paper3d --out "$work" --threads "$SVA_THREADS" ${SIM_ARGS:-} &&
    "$BUNDLE/sva" --quiet train --data "$work/train.svad" --out "$work/map.svam" --threads "$SVA_THREADS"
fi
wait
cat "$out"/.suite/*.out >"$out/suite.txt"
grep -hE '^[a-z_]+: [0-9]+ passed|FAILED' "$out/suite.txt"
suite_failed=$(($(grep -cE '^  FAILED' "$out/suite.txt") + agreement_failed))

# sva recognize with 1 and 2 groups of 64 sessions in flight: the double buffering's gain on this device, and the same
# bytes (recognize-in-flight.txt).
recognize_in_flight() {
  local t=$(($(left) * 30 / 100)) n r
  if ((t < 40)); then echo "recognize in flight: no time left" | tee "$out/recognize-in-flight.txt"; return; fi
  say "sva recognize, 1 and 2 groups in flight ($t s at most)"
  {
    "$BUNDLE/sva" --quiet recognize --write-sessions "$out/.suite/sessions.jsonl" --map "$work/map.svam" \
      --data "$work/test.svad" --trials 512 --max-readings 10
    for n in 1 2; do
      r=$SECONDS
      timeout $((t / 2)) "$BUNDLE/sva" --quiet recognize --map "$work/map.svam" --batch "$out/.suite/sessions.jsonl" \
        --out "$out/.suite/results-$n.jsonl" --backend vulkan --sessions-per-submission 64 --in-flight "$n"
      echo "in flight $n: exit $?, $((SECONDS - r)) s for 512 sessions of 10 readings"
    done
    cmp -s "$out/.suite/results-1.jsonl" "$out/.suite/results-2.jsonl" && echo "results: the same bytes" ||
      echo "results: DIFFER"
  } >"$out/recognize-in-flight.txt" 2>&1
  cat "$out/recognize-in-flight.txt"
}

# Runs a command within SECONDS (timeout's arguments), then says so when the budget's end stopped it, and counts a
# failure: the benchmarks' and the span models' one rule.
within() {
  timeout "$@"
  local rc=$?
  if ((rc == 124)); then echo "(stopped at the budget's end)"
  elif ((rc != 0)); then echo "(failed: exit $rc)"; suite_failed=$((suite_failed + 1)); fi
}

# One robot's session on this host's cores: its estimate timed with every thread, beside the model of the estimate's
# critical path on one thread (bench/estimate_speed's span probe), at 30 and 100 readings (estimate-span.txt).
estimate_span() {
  local t=$(($(left) * 10 / 100)) r exe=$BUNDLE/bench/estimate_speed
  if [[ ! -x $exe ]]; then echo "estimate span: this bundle has no bench/estimate_speed" | tee "$out/estimate-span.txt"; return; fi
  ((t >= 20)) || t=20  # a few seconds on paper3d: never left out for want of a share
  say "one session's estimate and its span on $SVA_THREADS threads ($t s at most)"
  for r in 30 100; do
    within $((t / 2)) "$exe" "$work/map.svam" "$work/test.svad" 1 "$r" 10 "$SVA_THREADS" 3
  done >"$out/estimate-span.txt" 2>&1
  cat "$out/estimate-span.txt"
}

# One session's update under the span probe, its loops split for 16 and for 8 threads (bench/speed/filter_speed.cpp):
# the model of issue 52's 16-against-8 goal on this host, beside bench-cpu-t8 and bench-cpu-t16's measured times.
update_span() {
  local t=$(($(left) * 5 / 100)) p exe=$BUNDLE/bench/filter_speed
  if [[ ! -x $exe ]]; then echo "update span: this bundle has no bench/filter_speed" | tee "$out/update-span.txt"; return; fi
  ((t >= 20)) || t=20
  say "one session's update and its span, split for 16 and 8 threads ($t s at most)"
  for p in 16 8; do
    SVA_THREADS=$p within $((t / 2)) "$exe" "$work/map.svam" "$work/test.svad" 3 100 "$p" 0 0 0 1
  done >"$out/update-span.txt" 2>&1
  grep 'span probe' "$out/update-span.txt"
}

# 64 sessions to 10 readings on 16 and on 2 threads (bench/speed/batch_speed.cpp), each measured with the accuracy it
# buys, then under the span probe: the model of the batch on 16 and on 2 cores (batch-span.txt). Issue 52's 64-session
# goal (16 threads >= 6x 2 threads) measured where the host has 16 cores, modelled on any.
batch_span() {
  local t=$(($(left) * 10 / 100)) p exe=$BUNDLE/bench/batch_speed
  if [[ ! -x $exe ]]; then echo "batch span: this bundle has no bench/batch_speed" | tee "$out/batch-span.txt"; return; fi
  ((t >= 50)) || t=50  # about 30 s on paper3d at 2 cores (the probe's two runs on one core, 11 s each)
  say "64 sessions to 10 readings and their span, on 16 and 2 threads ($t s at most)"
  for p in 16 2; do
    SVA_THREADS=$p within $((t / 2)) "$exe" "$work/map.svam" "$work/test.svad" 64 10 "$p" 1 full 1
  done >"$out/batch-span.txt" 2>&1
  cat "$out/batch-span.txt"
}

# Each benchmark at most its share of what is left, and at least 20 s while that much is left: a small share once cut
# a benchmark of a few seconds that had the time (the light estimates' one session, at a budget of 150 s).
bench() {  # NAME SHARE-OF-WHAT-IS-LEFT sva-bench-options...
  local name=$1 share=$2 t rest
  shift 2
  rest=$(left)
  if ((rest < 20)); then echo "bench $name: no time left" | tee "$out/bench-$name.txt"; return; fi
  t=$((rest * share / 100))
  ((t >= 20)) || t=20
  say "sva bench $name ($t s at most)"
  within "$t" "$BUNDLE/sva" --quiet bench --map "$work/map.svam" --data "$work/test.svad" --json "$out/.suite/bench-$name.json" \
    "$@" >"$out/bench-$name.txt" 2>&1
  grep -vE '^(cpu|vulkan)( batch)?: [0-9]+/' "$out/bench-$name.txt" | head -50
}
[[ -f $work/map.svam ]] || { echo "no paper3d map in $work: no benchmark" >&2; suite_failed=$((suite_failed + 1)); }
if [[ -f $work/map.svam ]]; then
  # Issue 52's goals first, so that a loan cut short still measures them; the diagnostics after.
  bench vulkan 40 --backend vulkan --trials 3 --batch 0 --readings 10,30,100
  # One session with light estimates (the belief's answer after every touch, the host fitting nothing): the touch goal
  # as restated (1.5 and 4 ms), now that a sharp belief's best bins are read from its band list (the band's floor).
  bench vulkan-light 8 --backend vulkan --trials 3 --batch 0 --readings 10,30,100 --estimate light
  # The CPU reference on the same machine, one session: what the device's update is weighed against (a few seconds).
  bench cpu 30 --backend cpu --trials 1 --batch 0 --readings 10,30,100
  bench vulkan-batch 50 --backend vulkan --trials 64 --batch 64 --readings 10,30
  # The same batch with light estimates (the belief's answer, no host fit): the batch goal as restated, half the rate at
  # which the bare hash scatter bounds its votes (scripts/device-check-summary.py); the host's fits after every reading
  # bound a batch of full estimates on 16 cores to about 2,300/s at 30 readings.
  bench vulkan-batch-light 15 --backend vulkan --trials 64 --batch 64 --readings 10,30 --estimate light
  estimate_span
  update_span
  batch_span
  # The CPU reference's scaling on the host's cores (issue 52's goals: one session on 16 threads >= 1.6x 8 threads;
  # 64 sessions on 16 threads >= 6x 2 threads: batch-span.txt), where the host has 16 of them.
  if (($(nproc) >= 16)); then
    SVA_THREADS=8 bench cpu-t8 20 --backend cpu --trials 1 --batch 0 --readings 30,100
    SVA_THREADS=16 bench cpu-t16 25 --backend cpu --trials 1 --batch 0 --readings 30,100
  else
    echo "CPU scaling: not measured ($(nproc) cores; it needs 16)"
  fi
  # The diagnostics: 3 hypotheses per estimate as sva recognize asks (the modes' path).
  bench vulkan-top3 15 --backend vulkan --trials 3 --batch 0 --readings 10,30 --top-k 3
  # The same with a camera's pose prior per session: est. subm. shows whether the device's key choice under a prior
  # keeps a robot's touch to one round trip, as lavapipe's tests say.
  bench vulkan-top3-prior 10 --backend vulkan --trials 3 --batch 0 --readings 10,30 --top-k 3 --pose-prior 5,10
  # The batch, full estimates, with matches of likelihood below 0.2 casting no vote: 2.5x fewer votes on paper3d
  # at about the same accuracy and errors in 100 CPU trials (docs/recognition.md, "Fewer votes"): what the device
  # makes of fewer votes.
  bench vulkan-batch-cut 10 --backend vulkan --trials 64 --batch 64 --readings 10,30 --likelihood-cutoff 0.2
  # The same batch with its tables warm (--warm on: one untimed group first, as a long study's later groups find
  # them): what the sessions' growth costs the batch (`growth ms`, 12.3 of 72 ms per submission at 10 readings in the
  # seventh run), and so whether tables sized ahead for a batch's first group would pay.
  bench vulkan-batch-warm 8 --backend vulkan --trials 64 --batch 64 --readings 10,30 --warm on
  # The sessions' belief passes side by side against one at a time (SVA_VK_SERIAL=1), by wall time: without the
  # timestamps around each dispatch, which may serialise them themselves (docs/vulkan-backend.md, "Batches").
  SVA_VK_TIMESTAMPS=0 bench vulkan-batch-untimed 10 --backend vulkan --trials 64 --batch 64 --readings 10
  SVA_VK_TIMESTAMPS=0 SVA_VK_SERIAL=1 bench vulkan-batch-serial 10 --backend vulkan --trials 64 --batch 64 --readings 10
  # On a GPU machine's host: 256 sessions per submission (the two groups in flight together that
  # Engine::sessions_per_submission gives an 80-141 GB GPU at the default bound, 105-186 each), then sva recognize's
  # double buffering.
  if (($(nproc) >= 16)); then
    bench vulkan-batch-256 40 --backend vulkan --trials 256 --batch 256 --readings 10,30
    recognize_in_flight
  fi
fi
tar -czf "$out/details.tgz" -C "$out" .suite .agreement 2>/dev/null
rm -rf "$out/.suite" "$out/.agreement"
if [[ -n ${ARCHIVE:-} ]]; then
  tar -czf "$ARCHIVE" -C "$(dirname "$out")" --exclude="$(basename "$out")/paper3d" "$(basename "$out")" ||
    { echo "run-device-check: could not write ARCHIVE '$ARCHIVE'" >&2; suite_failed=$((suite_failed + 1)); }
fi
say "done: $suite_failed failed test(s) or benchmark(s); files in $out"
((suite_failed == 0))
