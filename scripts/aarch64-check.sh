#!/usr/bin/env bash
# The aarch64 build, proven under emulation (issue 54; docs/reliability.md, "aarch64"): cross-builds the aarch64
# preset (scripts/setup.sh --aarch64 installs the cross compiler and the arm64 packages), runs the CPU-only suites
# under qemu-aarch64 (ctest runs each test through the toolchain's emulator), then the tiny scene's pipeline against
# x86-64's golden digests and `sva recognize` against this machine's build (tests/determinism/aarch64.py).
#   scripts/aarch64-check.sh [--suites-only]
# Needs the x86-64 ci build (build-ci/sva) for the batch comparison. Prints each step's time.
set -euo pipefail
repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$repo"
suites_only=0
case "${1:-}" in
  --suites-only) suites_only=1 ;;
  "") ;;
  *) echo "aarch64-check.sh: unknown option $1 (usage: scripts/aarch64-check.sh [--suites-only])" >&2; exit 2 ;;
esac
command -v aarch64-linux-gnu-g++ > /dev/null || { echo "no cross compiler: run scripts/setup.sh --aarch64" >&2; exit 2; }
command -v qemu-aarch64 > /dev/null || { echo "no qemu-aarch64: run scripts/setup.sh" >&2; exit 2; }
t0=$SECONDS
cmake --preset aarch64 > /dev/null
cmake --build --preset aarch64
echo "== aarch64 build: $((SECONDS - t0)) s"
t1=$SECONDS
# The CPU-only suites that finish under emulation (tests/determinism/aarch64.py's notes: the others, and every
# command that starts Embree or TBB's workers, are slower than this stage allows, or spin, under qemu-user).
ctest --test-dir build-aarch64 --output-on-failure --timeout 300 -j2 \
  -R "^(base|io|scene|votes|belief|cpu):"
echo "== aarch64 suites under qemu: $((SECONDS - t1)) s"
[ "$suites_only" = 1 ] && exit 0
t2=$SECONDS
python3 tests/determinism/aarch64.py --sva-aarch64 build-aarch64/sva --sva build-ci/sva --work build-aarch64/digests
echo "== aarch64 digests under qemu: $((SECONDS - t2)) s"
