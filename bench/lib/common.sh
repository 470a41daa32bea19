# Sourced by the bench scripts (bench/<folder>/*.sh): sets ROOT (the repository) and defines
#   find_sva                 sets SVA (the sva binary: $SVA if set, else the first one built in the usual build
#                            directories), or exits 2
#   bench_program NAME       prints the path of the bench program NAME (a CMake target of bench/CMakeLists.txt,
#                            built with SVA_BUILD_BENCH=ON into BUILD/bench/), or exits 2 saying how to build it
# One home for both, so that every script finds its binaries the same way.
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"

find_sva() {
  if [[ -z "${SVA:-}" ]]; then
    local c
    for c in "$ROOT/build/sva" "$ROOT/build-ci/sva" "$ROOT/build-sim/sva" "$ROOT/build-eval/sva" "$ROOT/build/host/cli/sva"; do
      [[ -x "$c" ]] && SVA="$c" && break
    done
  fi
  [[ -x "${SVA:-}" ]] || { echo "bench: no sva binary; build it or set SVA=/path/to/sva" >&2; exit 2; }
}

# BUILD_DIR, when set, is the only place looked in; else build-ci (the ci preset turns SVA_BUILD_BENCH on), then build.
# The scripts never build: a bench program is built with the rest (`cmake --build --preset ci`), so that the binary
# run is the one CI compiled, warnings as errors.
bench_program() {
  local name=$1 dirs=("$ROOT/build-ci" "$ROOT/build") d
  [[ -n "${BUILD_DIR:-}" ]] && dirs=("$BUILD_DIR")
  for d in "${dirs[@]}"; do
    [[ -x "$d/bench/$name" ]] && { echo "$d/bench/$name"; return; }
  done
  echo "bench: no $name in ${dirs[*]/%//bench}: build it (cmake --preset ci && cmake --build --preset ci," \
    "or configure with -DSVA_BUILD_BENCH=ON and build the target sva_bench_$name)" >&2
  exit 2
}
