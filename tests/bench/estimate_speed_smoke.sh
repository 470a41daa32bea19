#!/usr/bin/env bash
# bench/speed/estimate_speed.sh on the tiny scene: the stages' line with its digest, the same digest on 1 and 2
# threads (the estimate's answers do not depend on the thread count), a light estimate without the fits' stages and
# with other answers (8 readings: the full one fits), the span probe's line (a critical path within its work, and its
# stages' shares), and bad arguments refused by position and by name.
#   tests/bench/estimate_speed_smoke.sh SOURCE BUILD SVA PYTHON WORK
set -euo pipefail
source_dir=$1 sva=$3 work=$5
export BUILD_DIR=$2  # this build's bench program, not another build folder's
source "$(dirname "$0")/tiny_session_data.sh"
tiny_map "$sva" "$work" 20 12
line='^3 sessions at 8 readings, top 3, (full|light), [12] thread\(s\), best of 2: ms per session: estimate [0-9.]+ = belief [0-9.]+ \+ fits [0-9.]+ \+ verify [0-9.]+ \+ posterior [0-9.]+; CPU [0-9.]+ ms per session; digest [0-9a-f]{16}$'
one=$(bash "$source_dir/bench/speed/estimate_speed.sh" "$work/map.svam" "$work/test.svad" 3 8 2 1 3)
two=$(bash "$source_dir/bench/speed/estimate_speed.sh" "$work/map.svam" "$work/test.svad" 3 8 2 2 3)
echo "$one"
echo "$two"
grep -Eq "$line" <<< "$one" && grep -Eq "$line" <<< "$two" || { echo "missing or malformed line" >&2; exit 1; }
digest() { grep -Eo 'digest [0-9a-f]{16}' <<< "$1"; }
[ "$(digest "$one")" = "$(digest "$two")" ] || { echo "other answers on 2 threads" >&2; exit 1; }
# The span probe's line: each session's estimate alone, its critical path no longer than its work.
span='^one session alone, its loops split for 2 thread\(s\), timed on one: work ([0-9.]+) ms, span ([0-9.]+) ms \(longest [0-9.]+\): '
grep -Eq "$span" <<< "$two" || { echo "missing or malformed span line" >&2; exit 1; }
sed -nE "s/${span}.*/\1 \2/p" <<< "$two" | awk '{ exit !($2 > 0 && $2 <= $1) }' ||
  { echo "a span longer than its work, or none" >&2; exit 1; }
# The span by stage: each stage's share, none negative, together no more than the span (printed to 2 decimals).
stages='span by stage: belief ([0-9.]+) \+ fits ([0-9.]+) \+ verify ([0-9.]+) \+ posterior ([0-9.]+)$'
grep -Eq "$stages" <<< "$two" || { echo "missing or malformed span by stage" >&2; exit 1; }
paste <(sed -nE "s/${span}.*/\2/p" <<< "$two") <(sed -nE "s/.*${stages}/\1 \2 \3 \4/p" <<< "$two") |
  awk '{ sum = $2 + $3 + $4 + $5; exit !($3 > 0 && sum <= $1 + 0.02 && sum > 0.5 * $1) }' ||
  { echo "the stages' spans do not add up to the span" >&2; exit 1; }
light=$(bash "$source_dir/bench/speed/estimate_speed.sh" "$work/map.svam" "$work/test.svad" 3 8 2 1 3 light)
echo "$light"
grep -Eq "$line" <<< "$light" || { echo "missing or malformed light line" >&2; exit 1; }
grep -q ', light, .* fits 0.00 + verify 0.00 + ' <<< "$light" || { echo "a light estimate ran the fits" >&2; exit 1; }
[ "$(digest "$one")" != "$(digest "$light")" ] || { echo "light gave the full estimate's answers" >&2; exit 1; }
if err=$(bash "$source_dir/bench/speed/estimate_speed.sh" "$work/map.svam" "$work/test.svad" 3 8 2 1 3 fine 2>&1); then
  echo "accepted depth fine" >&2
  exit 1
fi
grep -q 'depth expects full or light, got "fine"' <<< "$err" || { echo "unclear refusal: $err" >&2; exit 1; }
if err=$(bash "$source_dir/bench/speed/estimate_speed.sh" "$work/map.svam" "$work/test.svad" 0 2>&1); then
  echo "accepted 0 sessions" >&2
  exit 1
fi
grep -q 'argument 3 ("0") is not a whole number in 1..4096' <<< "$err" || { echo "unclear refusal: $err" >&2; exit 1; }
