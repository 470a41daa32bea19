#!/usr/bin/env bash
# Benchmark of the Embree tactile simulator: the full paper3d dataset
# (10 objects x (1000 training + 100 test) readings) on THREADS threads
# (default 2). Prints wall time, readings per second and the convergence the
# speed buys. Goal: <= 60 s on 2 cores.
#   usage: bench/speed/simulate_paper3d.sh            (SVA=/path/to/sva THREADS=2 SEED=1 OUT=dir to override)
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/../lib/common.sh"
find_sva
THREADS="${THREADS:-2}"
SEED="${SEED:-1}"
OUT="${OUT:-$(mktemp -d /tmp/sva-bench-sim.XXXXXX)}"
mkdir -p "$OUT"  # tee writes the summary there before the simulator makes the folder
echo "== simulate paper3d: sva=$SVA threads=$THREADS seed=$SEED out=$OUT ($(nproc) cores)"
t0=$(date +%s.%N)
"$SVA" --quiet simulate --scene paper3d --out "$OUT" --seed "$SEED" --threads "$THREADS" | tee "$OUT/summary.txt"
t1=$(date +%s.%N)
readings=$(awk '/readings:/ {n += $2} END {print n}' "$OUT/summary.txt")
awk -v t0="$t0" -v t1="$t1" -v n="$readings" -v th="$THREADS" 'BEGIN {
  s = t1 - t0; printf "simulate paper3d: %d readings in %.1f s on %d threads = %.0f readings/s (goal: <= 60 s)\n", n, s, th, n / s }'
"$SVA" inspect "$OUT/train.svad" | sed -n '/object/,$p'
