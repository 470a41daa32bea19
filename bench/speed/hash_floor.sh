#!/usr/bin/env bash
# The floor of the CPU reference's hash-table work on this machine (bench/speed/hash_floor.cpp; docs/recognition.md,
# "The floor of the tables"): the ns of one addition into a pair's vote table and into a session's belief, and of one
# independent load per belief term, with the engine's own table. The program is the CMake target sva_bench_hash_floor
# (bench/CMakeLists.txt; BUILD_DIR picks the build, default build-ci then build).
#   bench/speed/hash_floor.sh [pair_slots pair_adds pair_bins belief_bins terms new_percent repeats]
# Defaults: paper3d at 30 readings (65,536 slots, 9,200 additions over 2,760 bins per pair; a belief of 1.2 M bins,
# 80,000 terms per update, a third of them new; best of 10).
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/../lib/common.sh"
hash_floor=$(bench_program hash_floor)
"$hash_floor" "$@"
