#!/usr/bin/env bash
# A batch of sessions on the CPU reference, an update and an estimate a step (bench/speed/batch_speed.cpp):
# session-updates per second on the workers, the CPU time and a digest of the last answers (the same on any thread
# count), and with span 1 the batch's work and critical path under a span probe, a model of it on `threads` cores. The
# program is the CMake target sva_bench_batch_speed (bench/CMakeLists.txt; BUILD_DIR picks the build, default build-ci
# then build).
#   bench/speed/batch_speed.sh MAP TEST [sessions=64] [readings=10] [threads=0] [top_k=1] [depth=full] [span=0]
# MAP, TEST: e.g. the demo's sva-demo/data/paper3d/{map.svam,test.svad} after `sva demo`.
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/../lib/common.sh"
[ $# -ge 2 ] || { sed -n '7,8p' "$0" >&2; exit 2; }
batch_speed=$(bench_program batch_speed)
"$batch_speed" "$@"
