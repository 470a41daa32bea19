#!/usr/bin/env bash
# The estimate's host stages timed on fixed sessions (bench/speed/estimate_speed.cpp): ms per session of each stage,
# best of the repeats, the CPU time per session and a digest of every answer (unchanged by a faster stage). The program
# is the CMake target sva_bench_estimate_speed (bench/CMakeLists.txt; BUILD_DIR picks the build, default build-ci then
# build).
#   bench/speed/estimate_speed.sh MAP TEST [sessions=6] [readings=30] [repeats=5] [threads=1] [top_k=3] [depth=full]
# depth: full, or light (the belief's answer alone: EstimateDepth::light, docs/recognition.md).
# MAP, TEST: e.g. the demo's sva-demo/data/paper3d/{map.svam,test.svad} after `sva demo`.
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/../lib/common.sh"
[ $# -ge 2 ] || { sed -n '6,8p' "$0" >&2; exit 2; }
estimate_speed=$(bench_program estimate_speed)
"$estimate_speed" "$@"
