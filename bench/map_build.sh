#!/usr/bin/env bash
# Benchmark of map training: clustering time, map build time, entries, bytes.
#   bench/map_build.sh DATA.svad [BUILD_DIR=build]       train on a dataset file
#   bench/map_build.sh --synthetic [BUILD_DIR=build]     on a synthetic 11,000-reading dataset (bench/map_synthetic.cpp)
# Prints the train summary (it carries the timings: wall and process CPU, which
# stays meaningful when other work shares the cores) and the inspect summary;
# also checks that 1 and 2 threads give the same bytes.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(dirname "$here")
data=${1:?usage: bench/map_build.sh DATA.svad|--synthetic [BUILD_DIR]}
build=${2:-$root/build}
sva=$build/sva
[[ -x $sva ]] || sva=$build/host/cli/sva
[[ -x $sva ]] || { echo "no sva binary in $build (build first)" >&2; exit 1; }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
if [[ $data == --synthetic ]]; then
  # Link the generator against the built core library.
  libs=$(find "$build" -name 'libsva_core.a' -o -name 'libsva_shaders.a' | tr '\n' ' ')
  c++ -std=c++20 -O2 -I"$root/host/include" -I"$root/host/src" "$here/map_synthetic.cpp" $libs $libs -lvulkan -lpthread -o "$tmp/map_synthetic"
  "$tmp/map_synthetic" "$tmp/synthetic.svad" 10 1100 1
  data=$tmp/synthetic.svad
fi
echo "== sva train ($data), 2 threads"
/usr/bin/time -f "wall %e s, user %U s, sys %S s, peak RSS %M KB" "$sva" --quiet train --data "$data" --out "$tmp/t2.svamap" --threads 2
echo "== sva train, 1 thread (determinism check)"
/usr/bin/time -f "wall %e s, user %U s, sys %S s, peak RSS %M KB" "$sva" --quiet train --data "$data" --out "$tmp/t1.svamap" --threads 1 | grep -E "classes|map "
if cmp -s "$tmp/t1.svamap" "$tmp/t2.svamap"; then echo "same bytes on 1 and 2 threads"; else echo "DIFFERENT bytes on 1 and 2 threads"; exit 1; fi
echo "== sva inspect"
"$sva" inspect "$tmp/t2.svamap"
ls -l "$tmp/t2.svamap" | awk '{print "map file bytes:", $5}'
