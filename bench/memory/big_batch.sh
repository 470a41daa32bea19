#!/usr/bin/env bash
# Many sessions through `sva recognize --batch` (sva issue 13, "Bounded memory, long sessions"): sessions files of
# each size in SESSIONS (default "1000 10000"; trials written by `sva recognize --write-sessions`, READINGS readings
# each), recognised in groups of GROUP sessions per submission. Prints, per size: wall time, time per session and per
# pair (a session of m readings votes m(m-1) pairs), and the peak resident memory (GNU time): memory and the time
# per session stay flat when the sessions stream through in groups, whatever their number.
# Env: SVA (binary), MAP and DATA (default the tiny scene in /work/mem: map.svam, test.svad; make them with
# `sva simulate --scene tiny --out DIR` and `sva train`), SESSIONS, READINGS (default 5), GROUP (default 64),
# BACKEND (default cpu), THREADS (SVA_THREADS, default 2), REFINE (on|off, default on), BUDGET (--belief-budget,
# default the library's), OUT (default /tmp/sva-bench/big_batch).
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/../lib/common.sh"
find_sva

MAP="${MAP:-/work/mem/map.svam}"
DATA="${DATA:-/work/mem/test.svad}"
SESSIONS="${SESSIONS:-1000 10000}"
READINGS="${READINGS:-5}"
GROUP="${GROUP:-64}"
BACKEND="${BACKEND:-cpu}"
export SVA_THREADS="${THREADS:-2}"
REFINE="${REFINE:-on}"
BUDGET="${BUDGET:-}"
OUT="${OUT:-/tmp/sva-bench/big_batch}"
mkdir -p "$OUT"
echo "== big batch: sva=$SVA map=$MAP data=$DATA sessions=\"$SESSIONS\" readings=$READINGS group=$GROUP backend=$BACKEND threads=$SVA_THREADS refine=$REFINE budget=${BUDGET:-default}"
printf '%9s %9s %8s %12s %10s %9s\n' sessions wall_s ms/sess us/pair peak_MiB results
for n in $SESSIONS; do
  sessions="$OUT/sessions_${n}x${READINGS}.jsonl"
  [[ -f "$sessions" ]] || "$SVA" --quiet recognize --write-sessions "$sessions" --map "$MAP" --data "$DATA" \
    --trials "$n" --max-readings "$READINGS" --seed 1
  /usr/bin/time -f '%e %M' -o "$OUT/time_$n.txt" "$SVA" --quiet recognize --map "$MAP" --batch "$sessions" \
    --out "$OUT/results_$n.jsonl" --backend "$BACKEND" --sessions-per-submission "$GROUP" --refine "$REFINE" \
    ${BUDGET:+--belief-budget "$BUDGET"} > "$OUT/recognize_$n.txt"
  read -r wall kib < "$OUT/time_$n.txt"
  lines=$(wc -l < "$OUT/results_$n.jsonl")
  awk -v n="$n" -v m="$READINGS" -v w="$wall" -v k="$kib" -v l="$lines" 'BEGIN {
    printf "%9d %9.1f %8.2f %12.1f %10.0f %9d\n", n, w, 1000 * w / n, 1e6 * w / (n * m * (m - 1)), k / 1024, l }'
done
