# Shared by bench/accuracy/eval_*.sh: simulate -> train -> eval (appearance baseline,
# then SVA with the baseline overlaid) -> the curves and the paper's targets.
# Sourced; expects SCENE, TARGETS (a python expression list, see below) and
# the defaults of TRIALS / MAX_READINGS set by the caller.
set -euo pipefail

source "$(dirname "${BASH_SOURCE[0]}")/../lib/common.sh"
find_sva

OUT="${OUT:-/tmp/sva-bench/$SCENE}"
SEED="${SEED:-1}"
BACKEND="${BACKEND:-cpu}"
THREADS_ARG=()
[[ -n "${THREADS:-}" ]] && THREADS_ARG=(--threads "$THREADS")
mkdir -p "$OUT"

echo "== $SCENE: sva=$SVA out=$OUT trials=$TRIALS max_readings=$MAX_READINGS seed=$SEED backend=$BACKEND"
t0=$(date +%s)
if [[ ! -f "$OUT/test.svad" || ! -f "$OUT/train.svad" ]]; then
  "$SVA" simulate --scene "$SCENE" --out "$OUT" --seed "$SEED" ${SIM_ARGS:-} "${THREADS_ARG[@]}"
fi
t1=$(date +%s)
if [[ ! -f "$OUT/map.svam" ]]; then
  "$SVA" train --data "$OUT/train.svad" --out "$OUT/map.svam" "${THREADS_ARG[@]}"
fi
t2=$(date +%s)
common=(eval --map "$OUT/map.svam" --data "$OUT/test.svad" --trials "$TRIALS" --max-readings "$MAX_READINGS"
        --seed "$SEED" --backend "$BACKEND" "${THREADS_ARG[@]}")
"$SVA" "${common[@]}" --method appearance --json "$OUT/eval_appearance.json" --csv "$OUT/eval_appearance.csv"
t3=$(date +%s)
"$SVA" "${common[@]}" --method sva --json "$OUT/eval_sva.json" --csv "$OUT/eval_sva.csv" \
  --plot "$OUT/eval.png" --compare "$OUT/eval_appearance.json"
t4=$(date +%s)
echo "== wall time: simulate $((t1 - t0)) s, train $((t2 - t1)) s, eval appearance $((t3 - t2)) s, eval sva $((t4 - t3)) s"
echo "== figure: $OUT/eval.png"

# Targets: lines "metric readings op value" checked against eval_sva.json.
python3 - "$OUT/eval_sva.json" "$TARGETS" <<'PY'
import json, sys
curve = {p["readings"]: p for p in json.load(open(sys.argv[1]))["curve"]}
ok = True
for line in sys.argv[2].strip().splitlines():
    metric, n, op, target = line.split()
    n, target = int(n), float(target)
    p = curve.get(n)
    v = None if p is None else p[metric]
    if v is not None and metric == "accuracy":
        v *= 100.0
    good = v is not None and (v >= target if op == ">=" else v <= target)
    ok &= good
    shown = "n/a" if v is None else f"{v:.3f}"
    print(f"target {metric} at {n} readings {op} {target:g}: measured {shown} -> {'MET' if good else 'NOT MET'}")
print("== all targets met" if ok else "== some targets not met")
PY
