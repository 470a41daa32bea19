#!/usr/bin/env bash
# The robustness sweep (sva issue 10): the same trials at a ladder of error
# levels. For each level X: `sva simulate --error-scale X` (every sigma and
# spread of the scene's errors block times X; 0 is the ideal world), `sva
# train`, `sva eval` (SVA, CPU backend, the same trial seed at every level);
# then `sva eval --sweep` tabulates accuracy and pose errors against the level
# and draws the figure. No Python.
# Env: SVA (binary), SCENE (default paper3d), LEVELS (default "0 0.5 1 2 4"),
# OUT (work root, reused: delete a level's folder to redo it; default
# /tmp/sva-bench/robustness_<scene>), TRAIN / TEST (readings per object,
# default 300 / 50: a tenth of paper3d's full map, so that the five levels fit
# ~10 minutes on 2 cores; "scene": the scene's own protocol, e.g. letters2d's grid), TRIALS (default 30), MAX_READINGS
# (default 30), READINGS (reported counts, default 5,10,20,30), SEED, THREADS
# (default 2), REFINE (on|off, default on), REPORT_ONLY=1 (only the report).
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/../lib/common.sh"
find_sva

SCENE="${SCENE:-paper3d}"
LEVELS="${LEVELS:-0 0.5 1 2 4}"
OUT="${OUT:-/tmp/sva-bench/robustness_$(basename "$SCENE" .json)}"
TRAIN="${TRAIN:-300}"
TEST="${TEST:-50}"
TRIALS="${TRIALS:-30}"
MAX_READINGS="${MAX_READINGS:-30}"
READINGS="${READINGS:-5,10,20,30}"
SEED="${SEED:-1}"
THREADS="${THREADS:-2}"
REFINE="${REFINE:-on}"
mkdir -p "$OUT"
echo "== robustness sweep: sva=$SVA scene=$SCENE levels=($LEVELS) out=$OUT train=$TRAIN test=$TEST" \
  "trials=$TRIALS max_readings=$MAX_READINGS seed=$SEED threads=$THREADS refine=$REFINE"

sweep=()
for x in $LEVELS; do
  dir="$OUT/level$x"
  mkdir -p "$dir"
  if [[ -z "${REPORT_ONLY:-}" ]]; then
    t0=$(date +%s)
    if [[ ! -f "$dir/train.svad" || ! -f "$dir/test.svad" ]]; then
      counts=()
      [[ "$TRAIN" == scene ]] || counts+=(--train "$TRAIN")
      [[ "$TEST" == scene ]] || counts+=(--test "$TEST")
      "$SVA" --quiet simulate --scene "$SCENE" --out "$dir" --error-scale "$x" "${counts[@]}" \
        --seed "$SEED" --threads "$THREADS" > "$dir/simulate.txt"
    fi
    [[ -f "$dir/map.svam" ]] || "$SVA" --quiet train --data "$dir/train.svad" --out "$dir/map.svam" \
      --threads "$THREADS" > "$dir/train.txt"
    "$SVA" --quiet eval --map "$dir/map.svam" --data "$dir/test.svad" --trials "$TRIALS" \
      --max-readings "$MAX_READINGS" --seed "$SEED" --backend cpu --threads "$THREADS" --refine "$REFINE" \
      --json "$dir/eval.json" --csv "$dir/eval.csv" > "$dir/eval.txt"
    echo "== level $x: $(($(date +%s) - t0)) s"
  fi
  sweep+=(--sweep "$x=$dir/eval.json")
done

"$SVA" eval "${sweep[@]}" --sweep-readings "$READINGS" --table "$OUT/sweep.md" --plot "$OUT/sweep.png"
echo "== table: $OUT/sweep.md, figure: $OUT/sweep.png"
