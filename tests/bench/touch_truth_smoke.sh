#!/usr/bin/env bash
# bench/active_touch/touch_truth.py on the tiny scene: the studies run and print their lines (the figures themselves are
# docs/evaluation.md's, on household10 and lookalikes).
#   tests/bench/touch_truth_smoke.sh SOURCE BUILD SVA PYTHON WORK
set -euo pipefail
source_dir=$1 build=$2 sva=$3 python=$4 work=$5
source "$(dirname "$0")/tiny_session_data.sh"
tiny_session_data "$sva" "$work" 60 3
run() {
  PYTHONPATH="$build/python" "$python" "$source_dir/bench/active_touch/touch_truth.py" \
    --map "$work/map.svam" --data "$work/test.svad" --random-csv "$work/random.csv" "$@"
}
out=$(run --readings 2 --dense "$work/dense/test.svad" --train "$work/train.svad")
echo "$out"
grep -q "^2 trials after 2 readings" <<< "$out" && grep -q "defaults *rank correlation [-+]" <<< "$out" &&
  grep -q "predicted readings *rank correlation [-+]" <<< "$out" && grep -q "(the best candidate)" <<< "$out" &&
  grep -q "^the place's share of the truth's variance: [-0-9]" <<< "$out" || { echo "missing lines" >&2; exit 1; }
# A bad value is refused by name, not a traceback.
if err=$(run --readings 9 2>&1); then echo "--readings 9 was accepted" >&2; exit 1; fi
grep -q "readings 9: .*fewer readings per trial" <<< "$err" || { echo "unclear refusal: $err" >&2; exit 1; }
printf 'trial,object\n0,0\n' > "$work/bad.csv"
if err=$(PYTHONPATH="$build/python" "$python" "$source_dir/bench/active_touch/touch_truth.py" \
  --map "$work/map.svam" --data "$work/test.svad" --random-csv "$work/bad.csv" 2>&1); then
  echo "a CSV without readings was accepted" >&2; exit 1
fi
grep -q "bad.csv: not a CSV of" <<< "$err" && ! grep -q Traceback <<< "$err" ||
  { echo "unclear refusal: $err" >&2; exit 1; }
if err=$(run --dense "$work/map.svam" 2>&1); then echo "a map was taken for a dense test set" >&2; exit 1; fi
grep -q "map.svam: not an sva dataset" <<< "$err" && ! grep -q Traceback <<< "$err" ||
  { echo "unclear refusal: $err" >&2; exit 1; }
