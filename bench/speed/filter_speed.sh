#!/usr/bin/env bash
# Benchmark of the Bayes filter (CPU reference backend): time per update at 10,
# 30 and 100 readings, votes per second, votes of mass 0, the error after the
# run and the peak RSS of the process.
#   bench/speed/filter_speed.sh [BUILD_DIR] [trials=3] [readings=100] [threads=2] [prune max_pairs cutoff span]
# span 1: the updates at 10, 30 and 100 readings under a span probe, a model of them on `threads` cores.
# BUILD_DIR: a build with the bench programs (SVA_BUILD_BENCH=ON; default build-ci, then build), whose sva it runs too.
# Simulates paper3d and trains its map first (cached in $SVA_BENCH_DIR, default /tmp/sva-bench-p3d).
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/../lib/common.sh"
filter_speed=$(BUILD_DIR=${1:-} bench_program filter_speed)
trials=${2:-3}
readings=${3:-100}
threads=${4:-2}
sva=$(dirname "$filter_speed")/../sva
[[ -x $sva ]] || { echo "no sva binary beside $filter_speed (build first)" >&2; exit 1; }
data=${SVA_BENCH_DIR:-/tmp/sva-bench-p3d}
mkdir -p "$data"
[[ -f $data/test.svad ]] || "$sva" --quiet simulate --scene paper3d --out "$data" --threads "$threads"
[[ -f $data/map.svam ]] || "$sva" --quiet train --data "$data/train.svad" --out "$data/map.svam" --threads "$threads"
SVA_THREADS=$threads "$filter_speed" "$data/map.svam" "$data/test.svad" "$trials" "$readings" "$threads" "${@:5}"
