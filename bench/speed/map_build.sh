#!/usr/bin/env bash
# Benchmark of map training: clustering time, map build time, entries, bytes.
#   bench/speed/map_build.sh DATA.svad [BUILD_DIR]      train on a dataset file
#   bench/speed/map_build.sh --synthetic [BUILD_DIR]    on a synthetic 11,000-reading dataset
#                                                       (bench/speed/map_synthetic.cpp)
# BUILD_DIR: the build whose sva (and map_synthetic: SVA_BUILD_BENCH=ON) runs; default the first built (build,
# build-ci).
# Prints the train summary (it carries the timings: wall and process CPU, which
# stays meaningful when other work shares the cores) and the inspect summary;
# also checks that 1 and 2 threads give the same bytes.
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/../lib/common.sh"
data=${1:?usage: bench/speed/map_build.sh DATA.svad|--synthetic [BUILD_DIR]}
build=${2:-}
[[ -n $build ]] && SVA=$build/sva
find_sva
sva=$SVA
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
train=()
if [[ $data == --synthetic ]]; then
  map_synthetic=$(BUILD_DIR=$build bench_program map_synthetic)
  "$map_synthetic" "$tmp/synthetic.svad" 10 1100 1
  data=$tmp/synthetic.svad
  # Its ellipsoids have no meshes: the verify stage reads the training contacts instead (sva train refuses otherwise).
  train=(--no-surfaces)
fi
echo "== sva train ($data), 2 threads"
/usr/bin/time -f "wall %e s, user %U s, sys %S s, peak RSS %M KB" "$sva" --quiet train --data "$data" --out "$tmp/t2.svamap" --threads 2 "${train[@]}"
echo "== sva train, 1 thread (determinism check)"
/usr/bin/time -f "wall %e s, user %U s, sys %S s, peak RSS %M KB" "$sva" --quiet train --data "$data" --out "$tmp/t1.svamap" --threads 1 "${train[@]}" | grep -E "classes|map "
if cmp -s "$tmp/t1.svamap" "$tmp/t2.svamap"; then echo "same bytes on 1 and 2 threads"; else echo "DIFFERENT bytes on 1 and 2 threads"; exit 1; fi
echo "== sva inspect"
"$sva" inspect "$tmp/t2.svamap"
ls -l "$tmp/t2.svamap" | awk '{print "map file bytes:", $5}'
