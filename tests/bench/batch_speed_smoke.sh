#!/usr/bin/env bash
# bench/speed/batch_speed.sh on the tiny scene: the batch's line with its accuracy and digest, the same digest on 1, 2
# and 16 threads (where the update cuts its largest pairs into pieces) and under the span probe, the probe's line (a
# critical path within its work, the model's bounds in order with the schedule between them), and bad arguments
# refused by position and by name.
#   tests/bench/batch_speed_smoke.sh SOURCE BUILD SVA PYTHON WORK
set -euo pipefail
source_dir=$1 sva=$3 work=$5
export BUILD_DIR=$2  # this build's bench program, not another build folder's
source "$(dirname "$0")/tiny_session_data.sh"
tiny_map "$sva" "$work" 40 12
run() { bash "$source_dir/bench/speed/batch_speed.sh" "$work/map.svam" "$work/test.svad" 5 6 "$@"; }
one=$(run 1)
two=$(run 2 1 full 0)
probed=$(run 16 1 full 1)
echo "$one"
echo "$probed"
line='^5 sessions x 6 readings, top 1, full, (1|2|16) thread\(s\): [0-9.]+ session-updates/s \(update [0-9.]+ \+ estimate [0-9.]+ ms a step\); CPU [0-9.]+ s; ([0-5])/5 objects right, median translation error [0-9.]+ mm; digest [0-9a-f]{16}$'
for out in "$one" "$two" "$probed"; do
  grep -Eq "$line" <<< "$out" || { echo "missing or malformed batch line" >&2; exit 1; }
done
digest() { grep -Eo 'digest [0-9a-f]{16}' <<< "$1"; }
[ "$(digest "$one")" = "$(digest "$two")" ] && [ "$(digest "$one")" = "$(digest "$probed")" ] ||
  { echo "other answers on 2 or 16 threads" >&2; exit 1; }
# Not vacuous: the tiny scene's sessions are mostly recognised after 6 readings.
[ "$(sed -nE "s#${line}#\2#p" <<< "$one")" -ge 3 ] || { echo "fewer than 3 of 5 objects right" >&2; exit 1; }
span='^under a span probe, its loops split for 16 thread\(s\), timed on one: work ([0-9.]+) ms \(update [0-9.]+ \+ estimate [0-9.]+\), span ([0-9.]+) ms \(update [0-9.]+ \+ estimate [0-9.]+\), scheduled on 16 ([0-9.]+) ms: on 16 cores between ([0-9.]+) and ([0-9.]+) session-updates/s, ([0-9.]+) as scheduled \(a model\)$'
grep -Eq "$span" <<< "$probed" || { echo "missing or malformed span line" >&2; exit 1; }
sed -nE "s#${span}#\1 \2 \3 \4 \5 \6#p" <<< "$probed" |
  awk '{ exit !($2 > 0 && $2 <= $1 && $3 >= $2 && $3 <= $1 && $4 <= $6 && $6 <= $5) }' ||
  { echo "a span longer than its work, or the bounds and the schedule out of order" >&2; exit 1; }
grep -q 'under a span probe' <<< "$one" && { echo "a span line without span 1" >&2; exit 1; }
if err=$(run 2 1 full 2 2>&1); then
  echo "accepted span 2" >&2
  exit 1
fi
grep -q 'argument 8 ("2") is not a whole number in 0..1' <<< "$err" || { echo "unclear refusal: $err" >&2; exit 1; }
if err=$(run 2 1 deep 2>&1); then
  echo "accepted depth deep" >&2
  exit 1
fi
grep -q 'depth expects full or light, got "deep"' <<< "$err" || { echo "unclear refusal: $err" >&2; exit 1; }
if err=$(bash "$source_dir/bench/speed/batch_speed.sh" "$work/map.svam" "$work/nope.svad" 2>&1); then
  echo "accepted a missing test file" >&2
  exit 1
fi
grep -q 'nope.svad' <<< "$err" || { echo "the refusal does not name the file: $err" >&2; exit 1; }
