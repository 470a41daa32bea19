#!/usr/bin/env bash
# Benchmark of the Bayes filter (CPU reference backend): time per update at 10,
# 30 and 100 readings, votes per second, votes of mass 0, the error after the
# run and the peak RSS of the process.
#   bench/filter_speed.sh [BUILD_DIR=build] [trials=3] [readings=100] [threads=2] [prune max_pairs cutoff]
# Simulates paper3d and trains its map first (cached in $SVA_BENCH_DIR, default /tmp/sva-bench-p3d).
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(dirname "$here")
build=${1:-$root/build}
trials=${2:-3}
readings=${3:-100}
threads=${4:-2}
sva=$build/sva
[[ -x $sva ]] || sva=$build/host/cli/sva
[[ -x $sva ]] || { echo "no sva binary at $sva (build first)" >&2; exit 1; }
data=${SVA_BENCH_DIR:-/tmp/sva-bench-p3d}
mkdir -p "$data"
[[ -f $data/test.svad ]] || "$sva" --quiet simulate --scene paper3d --out "$data" --threads "$threads"
[[ -f $data/map.svam ]] || "$sva" --quiet train --data "$data/train.svad" --out "$data/map.svam" --threads "$threads"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
# The build's own libraries (the package test installs other copies under the build directory).
lib() { find "$build" -name "lib$1.a" -not -path '*/package-test/*' | head -n 1; }
libs="$(lib sva_core) $(lib sva_io) $(lib sva_base)"
c++ -std=c++20 -O2 -I"$root/host/include" -I"$root/host/src" -I"$root/host/base/include" -I"$root/host/eval/include" \
  -I"$root/shaders/include" -I"$here" "$here/filter_speed.cpp" "$root/host/eval/src/bench/process_memory.cpp" $libs \
  -ltbb -lvulkan -lpthread -o "$tmp/filter_speed"
SVA_THREADS=$threads "$tmp/filter_speed" "$data/map.svam" "$data/test.svad" "$trials" "$readings" "$threads" "${@:5}"
