#!/usr/bin/env bash
# Recognition among many objects (sva issue 10): the household set at 10, 25
# and 50 objects (assets/scenes/household{10,25,50}.json, the first N of the
# same 50, same protocol). For each: simulate, train, `sva eval` (SVA, CPU
# backend) and `sva bench` (CPU, one session), then one table: map entries,
# map bytes on disk and per entry, train wall time, accuracy at 5/10/20/30
# readings, time per update and votes per update at 10 and 30 readings, and
# the time per vote, which stays flat when the update time grows no faster
# than the map entries the readings match.
# Env: SVA (binary), OUT (work root, reused: delete a householdN folder to
# redo it), COUNTS (default "10 25 50"), TRIALS (eval trials, default 50 at
# every size: trial t uses object t mod N), BENCH_TRIALS (default 5), SEED,
# THREADS (default 2), SIM_ARGS (extra `sva simulate` options), REPORT_ONLY=1
# (print the table of the runs already in OUT).
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/../lib/common.sh"
find_sva

OUT="${OUT:-/tmp/sva-bench/many_objects}"
COUNTS="${COUNTS:-10 25 50}"
TRIALS="${TRIALS:-50}"
BENCH_TRIALS="${BENCH_TRIALS:-5}"
SEED="${SEED:-1}"
THREADS="${THREADS:-2}"
mkdir -p "$OUT"
echo "== many objects: sva=$SVA out=$OUT counts=$COUNTS trials=$TRIALS bench_trials=$BENCH_TRIALS seed=$SEED threads=$THREADS"

now() { date +%s.%N; }
elapsed() { awk -v a="$(now)" -v b="$1" 'BEGIN { printf "%.1f\n", a - b }'; }
for n in $COUNTS; do
  [[ -n "${REPORT_ONLY:-}" ]] && break
  dir="$OUT/household$n"
  mkdir -p "$dir"
  if [[ ! -f "$dir/train.svad" || ! -f "$dir/test.svad" ]]; then
    t0=$(now)
    "$SVA" --quiet simulate --scene "household$n" --out "$dir" --seed "$SEED" --threads "$THREADS" ${SIM_ARGS:-}
    elapsed "$t0" > "$dir/simulate_seconds"
  fi
  if [[ ! -f "$dir/map.svam" ]]; then
    t0=$(now)
    "$SVA" --quiet train --data "$dir/train.svad" --out "$dir/map.svam" --threads "$THREADS"
    elapsed "$t0" > "$dir/train_seconds"
  fi
  t0=$(now)
  "$SVA" --quiet eval --map "$dir/map.svam" --data "$dir/test.svad" --trials "$TRIALS" --max-readings 30 \
    --seed "$SEED" --backend cpu --threads "$THREADS" --json "$dir/eval.json" --csv "$dir/eval.csv" > "$dir/eval.txt"
  elapsed "$t0" > "$dir/eval_seconds"
  "$SVA" --quiet bench --map "$dir/map.svam" --data "$dir/test.svad" --backend cpu --readings 10,30 \
    --trials "$BENCH_TRIALS" --batch 0 --seed "$SEED" --json "$dir/bench.json" > "$dir/bench.txt"
  echo "== household$n: simulate $(cat "$dir/simulate_seconds") s, train $(cat "$dir/train_seconds") s," \
    "eval $(cat "$dir/eval_seconds") s"
done

python3 - "$OUT" $COUNTS <<'PY'
import csv, json, os, sys
out, counts = sys.argv[1], sys.argv[2:]
rows = []
for n in counts:
    d = os.path.join(out, f"household{n}")
    ev_json = json.load(open(os.path.join(d, "eval.json")))
    ev = {p["readings"]: p for p in ev_json["curve"]}
    be = json.load(open(os.path.join(d, "bench.json")))
    bc = {p["readings"]: p for p in be["runs"][0]["curve"]}
    size = os.path.getsize(os.path.join(d, "map.svam"))
    with open(os.path.join(d, "eval.csv")) as f:
        trials = list(csv.DictReader(f))
    names = {t["object"]: t["object_name"] for t in trials}
    rows.append(dict(
        n=int(n), entries=be["map_entries"], mb=size / 1e6, bpe=size / be["map_entries"],
        train=float(open(os.path.join(d, "train_seconds")).read()),
        acc={r: ev[r]["accuracy"] * 100 for r in (5, 10, 20, 30)},
        err30=(ev[30]["translation_error_mm"], ev[30]["angular_error_deg"], ev[30]["inertial_error_mm"]),
        ms={r: ev[r]["update_ms"] for r in (10, 30)},  # median over the eval's trials
        votes={r: ev[r]["votes"] / ev_json["trials"] for r in (10, 30)},
        bench_ms={r: bc[r]["update_ms"] for r in (10, 30)},  # one session at a time
        wrong=[(t["object_name"], names.get(t["estimated_object"], t["estimated_object"]))
               for t in trials if t["readings"] == "30" and t["correct"] in ("0", "false")]))
print("\n| objects | map entries | map MB | B/entry | train s | acc 5 | acc 10 | acc 20 | acc 30 "
      "| trans / angle / inertial at 30 | ms/update 10 | ms/update 30 | votes/update 10 | votes/update 30 "
      "| ns/vote 30 | bench ms/update 10 | bench ms/update 30 |")
print("|" + "---|" * 17)
for r in rows:
    ns = r["ms"][30] * 1e6 / max(r["votes"][30], 1)
    print(f"| {r['n']} | {r['entries']:,} | {r['mb']:.1f} | {r['bpe']:.2f} | {r['train']:.1f} | "
          + " | ".join(f"{r['acc'][k]:.0f}%" for k in (5, 10, 20, 30))
          + " | {:.1f} mm / {:.1f}° / {:.1f} mm".format(*r["err30"])
          + f" | {r['ms'][10]:.0f} | {r['ms'][30]:.0f} | {r['votes'][10]:,.0f} | {r['votes'][30]:,.0f} | {ns:.0f}"
          + f" | {r['bench_ms'][10]:.0f} | {r['bench_ms'][30]:.0f} |")
base = rows[0]
print(f"\ngrowth against {base['n']} objects (the update time should grow no faster than the votes the matches cast):")
for r in rows[1:]:
    print(f"  {r['n']} objects: entries x{r['entries'] / base['entries']:.2f}, "
          f"votes/update at 30 x{r['votes'][30] / base['votes'][30]:.2f}, "
          f"ms/update at 30 x{r['ms'][30] / base['ms'][30]:.2f} (bench x{r['bench_ms'][30] / base['bench_ms'][30]:.2f})")
for r in rows:  # the trials still wrong after 30 readings, and what they were taken for
    print(f"  household{r['n']}: wrong at 30 readings: " + (", ".join(f"{a} (as {b})" for a, b in r["wrong"]) or "none"))
bad = [r for r in rows if r["bpe"] > 16]
print("goal <= 16 bytes per map entry: " + ("MET" if not bad else "NOT MET at " + ", ".join(str(r["n"]) for r in bad)))
PY
