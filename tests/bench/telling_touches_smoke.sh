#!/usr/bin/env bash
# bench/lookalikes/telling_touches.py on three families of lookalikes' meshes: two copies of one ball (no reading tells
# them apart, so only the random sessions run), a ball beside a cube with rounded edges (every reading tells; random
# sessions, at poses drawn as sva eval draws them, name the right one at 30 readings) and two cubes whose edge radii
# differ (only readings at the edges tell: both kinds of session run). The figures for the full scene are
# docs/evaluation.md's.
#   tests/bench/telling_touches_smoke.sh SOURCE BUILD SVA PYTHON WORK
set -euo pipefail
source_dir=$1 build=$2 sva=$3 python=$4 work=$5
rm -rf "$work" && mkdir -p "$work"
"$python" "$source_dir/tests/bench/family_scene.py" "$source_dir/assets/scenes/lookalikes.json" "$work/families.json" \
  three_families ball_64:twins ball_64:twins:ball_64_copy ball_74:apart cube_r12:apart cube_r2:edges cube_r6:edges
"$sva" --quiet simulate --scene "$work/families.json" --out "$work" --train 200 --test 60 --seed 1 --threads 2
"$sva" --quiet train --data "$work/train.svad" --out "$work/map.svam" --no-calibration --threads 2
touches() {
  PYTHONPATH="$build/python" "$python" "$source_dir/bench/lookalikes/telling_touches.py" "$work/map.svam" "$work/test.svad" \
    "$work/families.json" --trials 2 --points 4000 "$@"
}
out=$(touches --telling 3)
echo "$out"
grep -q "^twins .*random  *[0-9]* / *[0-9]*% (4)   3 telling - (too few readings)$" <<< "$out" &&
  grep -q "^apart .*random  *[0-9]* / 100% (4)" <<< "$out" &&
  grep -q "^edges .*3 telling  *[0-9]* / *[0-9]*% (4)$" <<< "$out" || { echo "unexpected sessions" >&2; exit 1; }
# Bad input is refused by name: a count outside 1-15, a family the scene lacks.
for bad in "--telling 0" "--families mugs"; do
  if touches $bad 2> "$work/err.txt"; then
    echo "$bad was accepted" >&2
    exit 1
  fi
  grep -q -e "--telling: each count" -e "mugs not a family" "$work/err.txt" || { cat "$work/err.txt" >&2; exit 1; }
done
