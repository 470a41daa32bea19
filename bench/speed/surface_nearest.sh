#!/usr/bin/env bash
# The verify stage's and the fine pose's primitive timed bare (bench/speed/surface_nearest.cpp): ns per query of the
# point of a map's mesh nearest to a point near its surface (SurfaceModel::nearest), the share found, a digest of
# every answer (unchanged by a faster search) and the model's resident memory. The program is the CMake target
# sva_bench_surface_nearest (bench/CMakeLists.txt; BUILD_DIR picks the build, default build-ci then build).
#   bench/speed/surface_nearest.sh MAP [queries per object (default 20000)] [repeats (default 5)]
# MAP: a map with meshes, e.g. the demo's: sva-demo/data/paper3d/map.svam after `sva demo`.
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/../lib/common.sh"
[ $# -ge 1 ] || { sed -n '6,7p' "$0" >&2; exit 2; }
surface_nearest=$(bench_program surface_nearest)
"$surface_nearest" "$@"
