#!/usr/bin/env bash
# bench/calibration/calibration_study.sh on the tiny scene: this build's program writes the three kinds of
# sessions and prints the families' ECE (the figures themselves are docs/evaluation.md's, on full-size scenes), and with
# 120 known sessions the fits of its two blocks of 60, and the surface weights (--weights).
#   tests/bench/calibration_study_smoke.sh SOURCE BUILD SVA PYTHON WORK
set -euo pipefail
source_dir=$1 build=$2 sva=$3 python=$4 work=$5
source "$(dirname "$0")/tiny_session_data.sh"
tiny_map "$sva" "$work" 20 12
out=$(BUILD_DIR="$build" PYTHON="$python" bash "$source_dir/bench/calibration/calibration_study.sh" "$work" 1 10 120 2>&1)
echo "$out"
for f in objects_held_out every_object test; do
  [[ -s $work/study.$f.jsonl ]] || { echo "no study.$f.jsonl" >&2; exit 1; }
done
[[ $(wc -l < "$work/study.test.jsonl") -eq 10 ]] || { echo "expected 10 test sessions" >&2; exit 1; }
grep -q "^temperature from every_object" <<< "$out" && grep -q "+ top label" <<< "$out" &&
  grep -q "^temperature fitted to the test sessions" <<< "$out" || { echo "missing lines" >&2; exit 1; }
[[ $(grep -c "^sessions [0-9]*-[0-9]*: " <<< "$out") -eq 2 ]] || { echo "expected the fits of 2 blocks of 60" >&2; exit 1; }
weights=$("$python" "$source_dir/bench/calibration/calibration_study.py" "$work/study" --weights)
[[ $(grep -c "^w [0-9.]*: right .*; held, refitted ECE" <<< "$weights") -eq 4 ]] &&
  [[ $(grep -c "^ranked at w [0-9.]*, calibrated at [0-9.]*: right .* ECE" <<< "$weights") -eq 2 ]] ||
  { echo "expected 4 surface weights and 2 ranking weights" >&2; exit 1; }
