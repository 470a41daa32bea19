#!/usr/bin/env bash
# The next touch with a belief that can be trusted (issue 22): mean readings to a right decision at P (the top object or
# "none of these" reaches P; a wrong or no decision counts READINGS + 1) for the random policy, the active one
# (sva::plan_next_touch) and a greedy oracle that tries candidate next readings of the true object
# (bench/active_touch/active_touch_oracle.py), on the same trials. Prints the share of the random-oracle gap active
# closes.
#   usage: bench/active_touch/active_touch_decide.sh DIR   (DIR holds train.svad, test.svad and map.svam, a
#          calibrated map; TRIALS=30 READINGS=20 P=0.95 CANDIDATES=20 SEED=1 THREADS=2 SVA=... PYTHON=.venv/bin/python)
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/../lib/common.sh"
find_sva
DIR="${1:?usage: bench/active_touch/active_touch_decide.sh DIR (with test.svad and map.svam)}"
TRIALS="${TRIALS:-30}"
READINGS="${READINGS:-20}"
P="${P:-0.95}"
CANDIDATES="${CANDIDATES:-20}"
SEED="${SEED:-1}"
THREADS="${THREADS:-2}"
PY="${PYTHON:-$ROOT/.venv/bin/python}"
common=(--quiet eval --map "$DIR/map.svam" --data "$DIR/test.svad" --backend cpu --threads "$THREADS" --seed "$SEED"
  --trials "$TRIALS" --max-readings "$READINGS" --stop-at "$P")
"$SVA" "${common[@]}" --csv "$DIR/decide_random.csv" --json "$DIR/decide_random.json" > "$DIR/decide_random.txt"
"$SVA" "${common[@]}" --policy active --json "$DIR/decide_active.json" > "$DIR/decide_active.txt"
PYTHONPATH="${PYTHONPATH:-$(dirname "$SVA")/python}" "$PY" "$ROOT/bench/active_touch/active_touch_oracle.py" \
  --map "$DIR/map.svam" --data "$DIR/test.svad" --random-csv "$DIR/decide_random.csv" --threshold "$P" \
  --candidates "$CANDIDATES" --max-readings "$READINGS" > "$DIR/decide_oracle.txt"
"$PY" - "$DIR" <<'PY'
import json, re, sys
d = sys.argv[1]
r = json.load(open(f"{d}/decide_random.json"))["stop"]
a = json.load(open(f"{d}/decide_active.json"))["stop"]
o = float(re.search(r"right decision at [0-9.]+: ([0-9.]+)", open(f"{d}/decide_oracle.txt").read()).group(1))
for name, s in (("random", r), ("active", a)):
    print(f"{name}: {s['mean_readings_to_right']:.2f} readings to a right decision ({s['decided']}/{s['trials']} decided, "
          f"{100 * (s['accuracy'] or 0):.1f}% of them right)")
print(f"oracle (greedy, candidates from the test readings): {o:.2f}")
gap = r["mean_readings_to_right"] - o
print(f"active closes {100 * (r['mean_readings_to_right'] - a['mean_readings_to_right']) / gap:.0f}% of the gap "
      f"(goal: at least 50%)" if gap > 0 else "no gap between random and the oracle")
PY
