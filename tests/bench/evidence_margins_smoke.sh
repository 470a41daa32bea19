#!/usr/bin/env bash
# bench/lookalikes/evidence_margins.py on two families of lookalikes' meshes (two balls of different sizes, two cubes
# whose edge radii differ): a small eval's evidence weighed again must name the estimate's own object at every trial
# and reading, and the margins' table must list both families. The figures for the full scene are the notebook's
# (docs/notes/evaluation-2026-11.md, "where the twins' evidence goes wrong").
#   tests/bench/evidence_margins_smoke.sh SOURCE BUILD SVA PYTHON WORK
set -euo pipefail
source_dir=$1 build=$2 sva=$3 python=$4 work=$5
rm -rf "$work" && mkdir -p "$work"
"$python" "$source_dir/tests/bench/family_scene.py" "$source_dir/assets/scenes/lookalikes.json" "$work/families.json" \
  two_families ball_64:balls ball_74:balls cube_r2:edges cube_r6:edges
"$sva" --quiet simulate --scene "$work/families.json" --out "$work" --train 150 --test 40 --seed 1 --threads 2
"$sva" --quiet train --data "$work/train.svad" --out "$work/map.svam" --no-calibration --threads 2
"$sva" --quiet eval --map "$work/map.svam" --data "$work/test.svad" --trials 8 --max-readings 8 --backend cpu \
  --threads 2 --evidence "$work/evidence.jsonl" > /dev/null
margins() {
  PYTHONPATH="$build/python" "$python" "$source_dir/bench/lookalikes/evidence_margins.py" "$@"
}
out=$(margins "$work/evidence.jsonl" "$work/map.svam" "$work/families.json" --readings 8 --weights 0,2)
echo "$out"
grep -q "^  (the weighing reproduces the estimate's object in 64 of 64 trial-readings)$" <<< "$out" &&
  grep -q "^  surface weight 2 " <<< "$out" &&
  grep -q "^at 8 readings: [0-9] of 8 trials wrong" <<< "$out" &&
  grep -q "^  balls  *[0-9]/4 " <<< "$out" &&
  grep -q "^  edges  *[0-9]/4 " <<< "$out" || { echo "unexpected tables" >&2; exit 1; }
# Bad input is refused by name: a line that is not evidence, a truth the map lacks, a reading count the run lacks, a
# weight below 0, a map whose objects the scene does not hold.
head -c 40 "$work/evidence.jsonl" > "$work/broken.jsonl"
"$python" - "$work/evidence.jsonl" "$work/unknown.jsonl" <<'EOF'
import json
import sys

rows = [json.loads(line) for line in open(sys.argv[1])]
rows[3]["map_object"] = None  # as --unknown-objects writes a truth the map lacks
open(sys.argv[2], "w").write("".join(json.dumps(r) + "\n" for r in rows))
EOF
refused() {
  local expect=$1
  shift
  if margins "$@" 2> "$work/err.txt"; then
    echo "accepted: $*" >&2
    exit 1
  fi
  grep -q -e "$expect" "$work/err.txt" || { cat "$work/err.txt" >&2; exit 1; }
}
refused "broken.jsonl, line 1: not a row of sva eval --evidence" "$work/broken.jsonl" "$work/map.svam" "$work/families.json"
refused "unknown.jsonl, line 4: trial [0-9]*'s object .* is not in the map" "$work/unknown.jsonl" "$work/map.svam" \
  "$work/families.json"
refused "no trial at that many readings" "$work/evidence.jsonl" "$work/map.svam" "$work/families.json" --readings 9
refused "must be finite and at least 0" "$work/evidence.jsonl" "$work/map.svam" "$work/families.json" --weights=-1
refused "object 'ball_64' is not in scene 'tiny'" "$work/evidence.jsonl" "$work/map.svam" tiny
echo "evidence_margins.py: tables and refusals as expected"
