#!/usr/bin/env bash
# Probabilities that can be trusted (issue 22, docs/evaluation.md "Calibration, none of these and when to stop"):
# per scene, the same trials with Eq 5's raw posterior (--calibration off) and the calibrated one: ECE, the share
# confidently wrong, decisions at --stop-at 0.95 and the accuracy curve; then "none of these" on held-out splits
# (a map trained without HELD objects, the full test set with --unknown-objects): ROC area and the share of
# unseen-object trials caught at <= 5% false rejection, at 15 readings.
#   usage: bench/calibration/calibration.sh   (SCENES="paper3d household50" TRIALS=50 READINGS=30 SPLITS=3 HELD=0.2
#                                  UNKNOWN_TRIALS=100 OUT=/tmp/sva-bench/calibration SVA=... THREADS=2 SEED=1)
# Simulates and trains what OUT lacks (household50: about 5 min with the calibration).
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/../lib/common.sh"
find_sva
SCENES="${SCENES:-paper3d household50}"
TRIALS="${TRIALS:-50}"
UNKNOWN_TRIALS="${UNKNOWN_TRIALS:-100}"
READINGS="${READINGS:-30}"
SPLITS="${SPLITS:-3}"
HELD="${HELD:-0.2}"
THREADS="${THREADS:-2}"
SEED="${SEED:-1}"
OUT="${OUT:-/tmp/sva-bench/calibration}"
echo "== calibration: sva=$SVA scenes=$SCENES trials=$TRIALS readings=$READINGS splits=$SPLITS held=$HELD out=$OUT"
summary() {  # JSON -> one line: ECE, confidently wrong, stop, accuracy at 2/5/10/15/30, unknown
  "${PYTHON:-python3}" - "$1" <<'PY'
import json, sys
j = json.load(open(sys.argv[1]))
c, s = j["calibration"], j.get("stop")
acc = {p["readings"]: p["accuracy"] for p in j["curve"]}
line = f"ECE {c['ece']:.4f}  confidently wrong {100 * c['confidently_wrong']:.2f}%"
if s and s["decided"]:
    line += f"  at 0.95: {s['decided']}/{s['trials']} decided, {100 * s['accuracy']:.1f}% right, {s['mean_readings']:.2f} readings"
line += "  accuracy " + " ".join(f"{n}:{100 * acc[n]:.1f}%" for n in (2, 3, 5, 10, 15, 30) if n in acc)
u = j.get("unknown_objects")
if u:
    line += (f"  unknown@{u['readings']}: ROC area {u['auc']:.3f}, caught {100 * u['caught_at_5']:.1f}% of "
             f"{u['unknown_trials']} at {100 * u['rejected_at_5']:.1f}% of {u['known_trials']} known rejected")
print(line)
PY
}
for scene in $SCENES; do
  dir="$OUT/$scene"
  mkdir -p "$dir"
  [[ -f "$dir/test.svad" ]] || "$SVA" --quiet simulate --scene "$scene" --out "$dir" --seed "$SEED" --threads "$THREADS"
  [[ -f "$dir/map.svam" ]] || "$SVA" --quiet train --data "$dir/train.svad" --out "$dir/map.svam" --threads "$THREADS" |
    tee "$dir/train.txt" | grep calibration
  common=(--quiet eval --map "$dir/map.svam" --data "$dir/test.svad" --backend cpu --threads "$THREADS" --seed "$SEED"
    --trials "$TRIALS" --max-readings "$READINGS" --stop-at 0.95)
  for cal in off on; do
    "$SVA" "${common[@]}" --calibration "$cal" --json "$dir/eval_$cal.json" --reliability "$dir/reliability_$cal.png" \
      > "$dir/eval_$cal.txt"
    echo "$scene calibration $cal: $(summary "$dir/eval_$cal.json")"
  done
  # Held-out splits: split k leaves out every object whose index i has (i + k) mod round(1 / HELD) == 0.
  names=$("${PYTHON:-python3}" -c "import json,sys; print(' '.join(o['name'] for o in json.load(open('$ROOT/assets/scenes/$scene.json'))['objects']))")
  every=$("${PYTHON:-python3}" -c "print(max(2, round(1 / $HELD)))")
  for k in $(seq 1 "$SPLITS"); do
    held=$(echo "$names" | tr ' ' '\n' | awk -v k="$k" -v e="$every" '(NR - 1 + k) % e == 0' | paste -sd, -)
    map="$dir/map_split$k.svam"
    [[ -f "$map" ]] || "$SVA" --quiet train --data "$dir/train.svad" --out "$map" --threads "$THREADS" \
      --exclude-objects "$held" > "$dir/train_split$k.txt"
    "$SVA" --quiet eval --map "$map" --data "$dir/test.svad" --backend cpu --threads "$THREADS" --seed "$SEED" \
      --trials "$UNKNOWN_TRIALS" --max-readings 15 --stop-at 0.95 --unknown-objects --json "$dir/unknown_split$k.json" \
      > "$dir/unknown_split$k.txt"
    echo "$scene split $k (held out: $held): $(summary "$dir/unknown_split$k.json")"
  done
done
