#!/usr/bin/env bash
# Choosing the next touch (issue 14, docs/evaluation.md "Choosing the next touch"): the same trials with the
# random policy (the paper's protocol) and the active one (sva::plan_next_touch, the true object's test reading
# nearest to the planned touch), on paper3d at the realistic default errors. Prints the readings until the true
# object holds >= 95% (mean per trial), the median pose errors at 10 and 20 readings, the plan's time for 10, 100
# and 1000 candidates beside an update's at 10 readings, and the issue's goals; draws both curves on one figure.
#   usage: bench/active_touch/active_touch.sh   (DATA=dir with train.svad, test.svad [, map.svam]; TRIALS=30
#            READINGS=20; TIMING_TRIALS=10; SIM=1 adds the active-sim policy; BOUND=1 adds the oracle bound of
#            bench/active_touch/active_touch_bound.py (needs the Python package in build-ci/python); SVA=... THREADS=2
#            OUT=dir)
# Without DATA it simulates paper3d (2 min) and trains the map (30 s) into OUT.
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/../lib/common.sh"
find_sva
TRIALS="${TRIALS:-30}"
READINGS="${READINGS:-20}"
TIMING_TRIALS="${TIMING_TRIALS:-10}"
THREADS="${THREADS:-2}"
SEED="${SEED:-1}"
OUT="${OUT:-/tmp/sva-bench/active_touch}"
DATA="${DATA:-$OUT}"
mkdir -p "$OUT"
echo "== active touch: sva=$SVA data=$DATA out=$OUT trials=$TRIALS readings=$READINGS seed=$SEED threads=$THREADS"
if [[ ! -f "$DATA/test.svad" ]]; then
  "$SVA" simulate --scene paper3d --out "$DATA" --seed "$SEED" --threads "$THREADS"
fi
MAP="$DATA/map.svam"
if [[ ! -f "$MAP" ]]; then
  MAP="$OUT/map.svam"
  [[ -f "$MAP" ]] || "$SVA" train --data "$DATA/train.svad" --out "$MAP" --threads "$THREADS"
fi
common=(--quiet eval --map "$MAP" --data "$DATA/test.svad" --backend cpu --threads "$THREADS" --seed "$SEED")

t0=$(date +%s)
"$SVA" "${common[@]}" --trials "$TRIALS" --max-readings "$READINGS" --json "$OUT/random.json" | tee "$OUT/random.txt"
t1=$(date +%s)
"$SVA" "${common[@]}" --trials "$TRIALS" --max-readings "$READINGS" --policy active --json "$OUT/active.json" \
  --plot "$OUT/active_vs_random.png" --compare "$OUT/random.json" | tee "$OUT/active.txt"
t2=$(date +%s)
curves=("$OUT/random.json" "$OUT/active.json")
if [[ "${SIM:-0}" == 1 ]]; then
  "$SVA" "${common[@]}" --trials "$TRIALS" --max-readings "$READINGS" --policy active-sim --json "$OUT/active_sim.json" \
    --plot "$OUT/active_sim_vs_random.png" --compare "$OUT/random.json" --compare "$OUT/active.json" |
    tee "$OUT/active_sim.txt"
  curves+=("$OUT/active_sim.json")
fi
t3=$(date +%s)
# Time per plan against the number of candidates (a few trials of 10 readings each).
for n in 10 100 1000; do
  "$SVA" "${common[@]}" --trials "$TIMING_TRIALS" --max-readings 10 --policy active --candidates-from hypotheses \
    --candidates "$n" \
    --json "$OUT/timing_$n.json" > /dev/null
done
t4=$(date +%s)
if [[ "${BOUND:-0}" == 1 ]]; then
  # The fewest readings to 95% any policy can reach after random's first touch (an oracle tries every second one).
  "$SVA" "${common[@]}" --trials "$TRIALS" --max-readings 6 --csv "$OUT/random6.csv" > /dev/null
  PYTHONPATH="${PYTHONPATH:-$(dirname "$SVA")/python}" "${PYTHON:-$ROOT/.venv/bin/python}" \
    "$ROOT/bench/active_touch/active_touch_bound.py" --map "$MAP" --data "$DATA/test.svad" --random-csv "$OUT/random6.csv" |
    tee "$OUT/bound.txt" | tail -3
fi
t5=$(date +%s)
echo "== wall time: random $((t1 - t0)) s, active $((t2 - t1)) s, active-sim $((t3 - t2)) s, timing $((t4 - t3)) s, bound $((t5 - t4)) s"
echo "== figure: $OUT/active_vs_random.png"

python3 - "$OUT" "${curves[@]}" <<'PY'
import json, sys
out, files = sys.argv[1], sys.argv[2:]
runs = {json.load(open(f))["policy"]: json.load(open(f)) for f in files}
def at(run, n, key):
    for p in run["curve"]:
        if p["readings"] == n:
            return p[key]
    return None
def fmt(v, f="%.2f"):
    return "n/a" if v is None else f % v
print("policy       readings-to-95% mean (median, reached)  | median translation mm / angle deg at 10 and 20 readings")
for name, r in runs.items():
    c = r["readings_to_95"]
    print(f"{name:12s} {fmt(c['mean']):>6s} ({fmt(c['median'], '%.1f')}, {c['reached']}/{c['trials']})"
          f"                  | 10: {fmt(at(r, 10, 'translation_error_mm'))} / {fmt(at(r, 10, 'angular_error_deg'))}"
          f"   20: {fmt(at(r, 20, 'translation_error_mm'))} / {fmt(at(r, 20, 'angular_error_deg'))}")
timing = {n: json.load(open(f"{out}/timing_{n}.json")) for n in (10, 100, 1000)}
update10 = at(timing[100], 10, "update_ms")
for n, r in timing.items():
    print(f"plan over {n:4d} candidates: median {fmt(r['plan_ms_median'], '%.3f')} ms per plan "
          f"(sampling + scoring, {r['trials']} trials x 10 readings)")
print(f"one update at 10 readings (median, same runs): {fmt(update10, '%.1f')} ms")
rnd, act = runs["random"], runs["active"]
goals = [
    ("mean readings to >= 95% (active <= 60% of random)", act["readings_to_95"]["mean"],
     0.6 * rnd["readings_to_95"]["mean"]),
    ("median translation mm at 10 (active) <= random at 20", at(act, 10, "translation_error_mm"),
     at(rnd, 20, "translation_error_mm")),
    ("median angle deg at 10 (active) <= random at 20", at(act, 10, "angular_error_deg"),
     at(rnd, 20, "angular_error_deg")),
    ("plan over 100 candidates < one update at 10 readings (ms)", timing[100]["plan_ms_median"], update10),
]
for what, value, bound in goals:
    ok = value is not None and bound is not None and value <= bound
    print(f"goal: {what}: {fmt(value, '%.3f')} vs {fmt(bound, '%.3f')}: {'met' if ok else 'NOT met'}")
PY
