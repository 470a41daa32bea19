#!/usr/bin/env bash
# bench/lookalikes/family_ceiling.py on two families of lookalikes' meshes: two copies of one ball (no touch can tell
# them apart: a guess between two, 0.50) and a ball beside a cube with rounded edges (apart by more than a millimetre
# almost everywhere: 1.00 once all six test readings are in). The figures for the full scene are docs/evaluation.md's.
#   tests/bench/family_ceiling_smoke.sh SOURCE BUILD SVA PYTHON WORK
set -euo pipefail
source_dir=$1 build=$2 sva=$3 python=$4 work=$5
rm -rf "$work" && mkdir -p "$work"
"$python" "$source_dir/tests/bench/family_scene.py" "$source_dir/assets/scenes/lookalikes.json" "$work/families.json" \
  two_families ball_64:twins ball_64:twins:ball_64_copy ball_74:apart cube_r12:apart
"$sva" --quiet simulate --scene "$work/families.json" --out "$work" --train 1 --test 6 --seed 1 --threads 2
ceiling() {
  PYTHONPATH="$build/python" "$python" "$source_dir/bench/lookalikes/family_ceiling.py" "$work/test.svad" "$work/families.json" \
    --draws 20 --points 4000 "$@"
}
out=$(ceiling --gaps 1)
echo "$out"
grep -q "^twins  *gap  *1.0 mm .*ceiling 0.50 / 0.50 / 0.50 / 0.50$" <<< "$out" &&
  grep -q "^apart  *gap  *1.0 mm .*ceiling .* / 1.00$" <<< "$out" || { echo "unexpected ceilings" >&2; exit 1; }
# Bad input: a gap that is not a number is refused by name.
if ceiling --gaps two 2> "$work/err.txt"; then
  echo "a gap of 'two' was accepted" >&2
  exit 1
fi
grep -q "gaps 'two'" "$work/err.txt" || { cat "$work/err.txt" >&2; exit 1; }
