#!/usr/bin/env bash
# bench/speed/filter_speed.cpp on the tiny scene: its update line, the span probe's line (a critical path within its
# work, on the model's 16 cores), the same answers with the probe and without it and on 1 and 16 threads (where the
# CPU update cuts its pairs into pieces), and bad arguments refused by position and by name.
#   tests/bench/filter_speed_smoke.sh SOURCE BUILD SVA PYTHON WORK
set -euo pipefail
source_dir=$1 sva=$3 work=$5
export BUILD_DIR=$2  # this build's bench program, not another build folder's
source "$source_dir/bench/lib/common.sh"
filter_speed=$(bench_program filter_speed)
source "$(dirname "$0")/tiny_session_data.sh"
tiny_map "$sva" "$work" 80 20
run() { "$filter_speed" "$work/map.svam" "$work/test.svad" 3 10 "$@"; }
one=$(run 1)
many=$(run 16)
probed=$(run 16 0 0 0 1)
echo "$one"
echo "$probed"
grep -Eq '^update at reading  10: wall median [0-9.]+ s' <<< "$one" || { echo "missing update line" >&2; exit 1; }
# The answers: every trial's object and probability, and the error after the run.
answers() { grep -E '^(trial|after)' <<< "$1"; }
[ "$(answers "$one")" = "$(answers "$many")" ] || { echo "other answers on 16 threads" >&2; exit 1; }
[ "$(answers "$one")" = "$(answers "$probed")" ] || { echo "other answers under the span probe" >&2; exit 1; }
span='^update at reading  10 under a span probe, its loops split for 16 threads: work median ([0-9.]+) ms, span median ([0-9.]+) ms \(3 trials\); on 16 cores of this machine.s kind between ([0-9.]+) and ([0-9.]+) ms, as scheduled ([0-9.]+) ms \(a model\)$'
grep -Eq "$span" <<< "$probed" || { echo "missing or malformed span line" >&2; exit 1; }
sed -nE "s/${span}/\1 \2 \3 \4 \5/p" <<< "$probed" | awk '{ exit !($2 > 0 && $2 <= $1 && $3 <= $5 && $5 <= $4) }' ||
  { echo "a span longer than its work, or the bounds and the schedule out of order" >&2; exit 1; }
if err=$("$filter_speed" "$work/map.svam" "$work/test.svad" 3 10 16 0 0 0 2 2>&1); then
  echo "accepted span 2" >&2
  exit 1
fi
grep -q 'argument 9 ("2") is not a whole number in 0..1' <<< "$err" || { echo "unclear refusal: $err" >&2; exit 1; }
if err=$("$filter_speed" "$work/map.svam" "$work/test.svad" 3 10 2 1.5 2>&1); then
  echo "accepted prune 1.5" >&2
  exit 1
fi
grep -q 'argument 6 ("1.5") is not a number in 0..1' <<< "$err" || { echo "unclear refusal: $err" >&2; exit 1; }
