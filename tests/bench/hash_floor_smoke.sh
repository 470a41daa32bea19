#!/usr/bin/env bash
# bench/speed/hash_floor.sh on small tables: this build's program (the engine's table) prints both lines (the figures
# themselves are docs/recognition.md's, at paper3d's sizes); a bad argument is refused with its position, and a belief
# too full for an update's new bins is refused rather than timed while it grows.
#   tests/bench/hash_floor_smoke.sh SOURCE BUILD SVA PYTHON WORK
set -euo pipefail
source_dir=$1
export BUILD_DIR=$2  # this build's bench program, not another build folder's
out=$(bash "$source_dir/bench/speed/hash_floor.sh" 4096 1000 800 20000 5000 33 2)
echo "$out"
grep -Eq "^pair table: 4096 slots, 1000 additions over 800 bins per pair: [0-9.]+ ns per addition$" <<< "$out" &&
  grep -Eq "^belief: 20000 bins \([0-9]+ MB\), 5000 terms, 33% new: [0-9.]+ ns per addition, [0-9.]+ ns with each batch.s slots loaded first, [0-9.]+ ns per independent load \(best of [12]\)$" \
    <<< "$out" || { echo "missing or malformed lines" >&2; exit 1; }
if err=$(bash "$source_dir/bench/speed/hash_floor.sh" 4096 1000 2000 2>&1); then echo "accepted more bins than additions" >&2; exit 1; fi
grep -q 'argument 3 ("2000") is not a whole number in 1..1000' <<< "$err" || { echo "unclear refusal: $err" >&2; exit 1; }
if err=$(bash "$source_dir/bench/speed/hash_floor.sh" 4096 1000 800 1000 5000 100 2 2>&1); then echo "timed a belief that grew" >&2; exit 1; fi
grep -q "has no room for the new bins" <<< "$err" || { echo "unclear refusal: $err" >&2; exit 1; }
