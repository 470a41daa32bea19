#!/usr/bin/env bash
# A long recognition session (sva issue 13, "Bounded memory, long sessions"): one `sva eval` trial of READINGS
# readings (default 1000) with a belief budget, while a sampler records the process's resident memory once a
# second. Prints, at 100, 300 and READINGS readings (and the checkpoints in CHECKPOINTS): the time per update, the
# time per pair (an update at t readings votes 2(t-1) pairs, so a flat time per pair means no slow-down beyond what
# the pairs cost), the votes per update, and the resident memory when the session passed that count, then the peak.
# Memory flat beyond ~100 readings is the belief budget at work (docs/recognition.md, "Bounded memory").
# Env: SVA (binary), MAP and DATA (default paper3d: /work/p3d/map2.svam, /work/p3d/test.svad; a tiny scene's map
# and test set make it quick), READINGS (default 1000), BUDGET (--belief-budget, default the library's 4194304
# bins; 0 = unbounded), BACKEND (default cpu), THREADS (default 2), SEED (default 1), CHECKPOINTS (default
# "10 100 300"), MAX_PAIRS (--max-pairs: pairs per update, both orders counted; default 0, the exact filter; 58 pairs
# the new reading with the 29 most recent ones), OUT (default /tmp/sva-bench/long_session).
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/../lib/common.sh"
find_sva

MAP="${MAP:-/work/p3d/map2.svam}"
DATA="${DATA:-/work/p3d/test.svad}"
READINGS="${READINGS:-1000}"
BUDGET="${BUDGET:-4194304}"
BACKEND="${BACKEND:-cpu}"
THREADS="${THREADS:-2}"
SEED="${SEED:-1}"
CHECKPOINTS="${CHECKPOINTS:-10 100 300}"
MAX_PAIRS="${MAX_PAIRS:-0}"
OUT="${OUT:-/tmp/sva-bench/long_session}"
mkdir -p "$OUT"
echo "== long session: sva=$SVA map=$MAP data=$DATA readings=$READINGS budget=$BUDGET max_pairs=$MAX_PAIRS backend=$BACKEND threads=$THREADS seed=$SEED"

"$SVA" --quiet eval --map "$MAP" --data "$DATA" --trials 1 --max-readings "$READINGS" --seed "$SEED" \
  --belief-budget "$BUDGET" --max-pairs "$MAX_PAIRS" --backend "$BACKEND" --threads "$THREADS" --json "$OUT/eval.json" > "$OUT/eval.txt" &
pid=$!
start=$(date +%s.%N)
: > "$OUT/rss.tsv"
while kill -0 "$pid" 2> /dev/null; do
  rss=$(awk '/^VmRSS/ { print $2 }' "/proc/$pid/status" 2> /dev/null || true)
  hwm=$(awk '/^VmHWM/ { print $2 }' "/proc/$pid/status" 2> /dev/null || true)
  [[ -n "$rss" ]] && echo "$(awk -v a="$(date +%s.%N)" -v b="$start" 'BEGIN { printf "%.2f", a - b }') $rss $hwm" >> "$OUT/rss.tsv"
  sleep 1
done
wait "$pid"
wall=$(awk -v a="$(date +%s.%N)" -v b="$start" 'BEGIN { printf "%.1f", a - b }')

python3 - "$OUT/eval.json" "$OUT/rss.tsv" "$READINGS" "$CHECKPOINTS" "$wall" "$MAX_PAIRS" << 'PY'
import json, sys
max_pairs = int(sys.argv[6])
curve = json.load(open(sys.argv[1]))["curve"]
samples = [tuple(map(float, l.split())) for l in open(sys.argv[2]) if l.strip()]
n = int(sys.argv[3])
marks = sorted({int(c) for c in sys.argv[4].split()} | {n})
# The session's clock: the updates' own times, summed (setup before the first update is the first sample's offset).
elapsed, total = [], 0.0
for p in curve:
    total += p["update_ms"] / 1000.0
    elapsed.append(total)
setup = max(0.0, (samples[-1][0] if samples else 0.0) - total) if samples else 0.0
def rss_at(t):
    best = None
    for s in samples:
        if s[0] <= t + setup: best = s
    return best[1] / 1024 if best else float("nan")
print(f"{'readings':>8} {'ms/update':>10} {'pairs':>6} {'us/pair':>8} {'votes/update':>13} {'RSS MiB':>8}")
for m in marks:
    if m > len(curve): continue
    p = curve[m - 1]
    pairs = min(2 * (m - 1), max_pairs) if max_pairs > 0 else 2 * (m - 1)
    per_pair = p["update_ms"] * 1000.0 / pairs if pairs else float("nan")
    print(f"{m:>8} {p['update_ms']:>10.1f} {pairs:>6} {per_pair:>8.1f} {p['votes']:>13} {rss_at(elapsed[m - 1]):>8.0f}")
peak = max((s[2] for s in samples), default=float("nan")) / 1024
print(f"peak RSS {peak:.0f} MiB; accuracy at {n}: {curve[-1]['accuracy']:.0%}; wall {sys.argv[5]} s")
PY
