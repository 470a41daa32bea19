#!/usr/bin/env bash
# bench/active_touch/place_oracle.py on the tiny scene: every way of valuing a place (the truth, the draws, the belief's
# hypotheses fitted and predicting from the training set, its modes, the true object at the belief's pose, at a noisy
# pose and over poses drawn about it) runs each trial to a decision and prints the summary (the figures themselves are
# docs/evaluation.md's, on household10); bad values are refused by name.
#   tests/bench/place_oracle_smoke.sh SOURCE BUILD SVA PYTHON WORK
set -euo pipefail
source_dir=$1 build=$2 sva=$3 python=$4 work=$5
source "$(dirname "$0")/tiny_session_data.sh"
tiny_session_data "$sva" "$work" 150 4
run() {
  PYTHONPATH="$build/python" "$python" "$source_dir/bench/active_touch/place_oracle.py" --map "$work/map.svam" \
    --data "$work/test.svad" --dense "$work/dense/test.svad" --random-csv "$work/random.csv" --max-readings 6 \
    --threshold 0.7 --candidates 4 --near-mm 8 --near-deg 40 "$@"
}
modes=("" --see-draws "--value hypotheses --refine --train $work/train.svad" "--value true-object"
  "--value modes --modes 4" "--value noisy-truth --pose-error 1,5"
  "--value noisy-truth --pose-error 1,5 --pose-samples 3" "--value hypotheses --pose-samples 2 --spread covariance")
for mode in "${modes[@]}"; do
  # shellcheck disable=SC2086  # the mode is a list of options
  out=$(run $mode)
  echo "$out"
  # Each trial's readings to a right decision lie in 1..7 (7: none within 6 readings).
  grep -qE "^trials 2: .* mean readings to a right decision at 0.7: [1-7]\.[0-9]{2} " <<< "$out" &&
    [[ $(grep -cE '^ +[01] +[a-z_]+ +[1-7]$' <<< "$out") == 2 ]] || { echo "missing lines ($mode)" >&2; exit 1; }
done
if err=$(run --near-deg 0 2>&1); then echo "--near-deg 0 was accepted" >&2; exit 1; fi
grep -q "near-deg in (0, 180\], got" <<< "$err" && ! grep -q Traceback <<< "$err" ||
  { echo "unclear refusal: $err" >&2; exit 1; }
if err=$(run --value noisy-truth --pose-error 1 2>&1); then echo "--pose-error 1 was accepted" >&2; exit 1; fi
grep -q 'pose-error: expected MM,DEG (two numbers >= 0), got "1"' <<< "$err" && ! grep -q Traceback <<< "$err" ||
  { echo "unclear refusal: $err" >&2; exit 1; }
if err=$(run --value noisy-truth --pose-samples 0 2>&1); then echo "--pose-samples 0 was accepted" >&2; exit 1; fi
grep -q "pose-samples must be at least 1, got 0" <<< "$err" && ! grep -q Traceback <<< "$err" ||
  { echo "unclear refusal: $err" >&2; exit 1; }
if err=$(run --value noisy-truth --spread covariance --pose-samples 2 2>&1); then
  echo "--spread covariance was accepted without a mode" >&2
  exit 1
fi
grep -q "spread covariance: --value noisy-truth has no mode covariance" <<< "$err" && ! grep -q Traceback <<< "$err" ||
  { echo "unclear refusal: $err" >&2; exit 1; }
if err=$(run --near-mm 0.001 2>&1); then echo "a dense set without neighbours was accepted" >&2; exit 1; fi
grep -q "no place of .* with a neighbour within 0.001 mm" <<< "$err" && ! grep -q Traceback <<< "$err" ||
  { echo "unclear refusal: $err" >&2; exit 1; }
if err=$(run --dense "$work/map.svam" 2>&1); then echo "a map was taken for a dense test set" >&2; exit 1; fi
grep -q "map.svam: not an sva dataset" <<< "$err" && ! grep -q Traceback <<< "$err" ||
  { echo "unclear refusal: $err" >&2; exit 1; }
