#!/usr/bin/env bash
# Look-alikes (docs/evaluation.md, "Look-alikes"): the lookalikes scene (15 families of near-twins) and household100
# (household50 plus the families), and by default household50 and paper3d too, so that the change shows on the
# scenes it must not worsen. For each: simulate, train (timed, peak memory), then `sva eval` twice on the same
# trials: the paper's method (pairs only, `--surface-check off`) and sva's default (with the surface check), each
# with the confusion matrices at 15 and 30 readings, the stop rule at 0.95 and the reliability diagram. Prints one
# table of accuracy, pose, calibration, decisions and time per update.
# Env: SVA (binary), OUT (work root, reused: delete a scene's folder to redo it), SCENES (default
# "lookalikes household100 household50 paper3d"), TRIALS (default: one per object, at least 50), SEED, THREADS
# (default 2), REPORT_ONLY=1 (the table of the runs in OUT). About 75 minutes on 2 cores for the default scenes.
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/../lib/common.sh"
find_sva

OUT="${OUT:-/tmp/sva-bench/lookalikes}"
SCENES="${SCENES:-lookalikes household100 household50 paper3d}"
SEED="${SEED:-1}"
THREADS="${THREADS:-2}"
mkdir -p "$OUT"
echo "== look-alikes: sva=$SVA out=$OUT scenes=$SCENES seed=$SEED threads=$THREADS"

timed() {  # FILE CMD...: runs CMD, writes "wall_s peak_kB" to FILE
  local file=$1
  shift
  /usr/bin/time -f "%e %M" -o "$file" "$@"
}

for scene in $SCENES; do
  [[ -n "${REPORT_ONLY:-}" ]] && break
  dir="$OUT/$scene"
  mkdir -p "$dir"
  [[ -f "$dir/test.svad" ]] || "$SVA" --quiet simulate --scene "$scene" --out "$dir" --seed "$SEED" --threads "$THREADS"
  [[ -f "$dir/map.svam" ]] ||
    timed "$dir/train.time" "$SVA" --quiet train --data "$dir/train.svad" --out "$dir/map.svam" --threads "$THREADS" \
      > "$dir/train.txt"
  objects=$("$SVA" --quiet inspect "$dir/map.svam" | awk '/^  objects/ {print $2; exit}')
  trials="${TRIALS:-$((objects > 50 ? objects : 50))}"
  for run in pairs check; do
    [[ -f "$dir/$run.json" ]] && continue
    extra=()
    [[ $run == pairs ]] && extra=(--surface-check off)
    "$SVA" --quiet eval --map "$dir/map.svam" --data "$dir/test.svad" --trials "$trials" --max-readings 30 \
      --seed "$SEED" --backend cpu --threads "$THREADS" --stop-at 0.95 --confusion "$dir/$run.confusion.json" \
      --json "$dir/$run.json" --plot "$dir/$run.png" "${extra[@]}" > "$dir/$run.txt"
  done
done

python3 - "$OUT" $SCENES <<'PY'
import json, os, sys
out, scenes = sys.argv[1], sys.argv[2:]
print("| scene | method | acc 5 | acc 10 | acc 15 | acc 30 | trans / angle at 30 | ECE | conf. wrong | decisions at 0.95 right | ms/update 15 | ms/update 30 | train s / peak MB |")
print("|---|---|---|---|---|---|---|---|---|---|---|---|---|")
for scene in scenes:
    d = os.path.join(out, scene)
    wall, peak = open(os.path.join(d, "train.time")).read().split()[:2] if os.path.exists(os.path.join(d, "train.time")) else ("-", "0")
    for run, label in (("pairs", "pairs only (paper)"), ("check", "surface check")):
        f = os.path.join(d, f"{run}.json")
        if not os.path.exists(f):
            continue
        j = json.load(open(f))
        c = {p["readings"]: p for p in j["curve"]}
        acc = lambda n: f'{100 * c[n]["accuracy"]:.0f}%' if n in c else "-"
        p30 = c.get(30, {})
        pose = (f'{p30["translation_error_mm"]:.2f} mm / {p30["angular_error_deg"]:.2f}°'
                if p30.get("translation_error_mm") is not None else "-")
        ms = lambda n: f'{c[n]["update_ms"]:.0f}' if n in c and c[n]["update_ms"] is not None else "-"
        cal, stop = j["calibration"], j.get("stop", {})
        decided = (f'{100 * stop["accuracy"]:.1f}% ({stop["decided"]} of {stop["trials"]})'
                   if stop.get("accuracy") is not None else "-")
        print(f'| {scene} | {label} | {acc(5)} | {acc(10)} | {acc(15)} | {acc(30)} | {pose} | {cal["ece"]:.4f} | '
              f'{100 * cal["confidently_wrong"]:.2f}% | {decided} | {ms(15)} | {ms(30)} | {wall} / {int(peak) // 1024} |')
PY
