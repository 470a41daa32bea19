#!/usr/bin/env bash
# The test command's steps, after scripts/setup.sh (README: `bash scripts/setup.sh && bash scripts/test.sh`, which
# .ci/run runs). Each stage says what it runs and how long it took; a table of the times closes the run. Stops at the
# first failing stage, naming it.
#   scripts/test.sh [STAGE...]     (default: every stage, in this order; names as printed, e.g. `scripts/test.sh pip`)
set -euo pipefail
cd "$(dirname "$0")/.."
repo="$PWD"

# One compiler cache for every build of the run (scripts/setup.sh installs ccache; CMakeLists.txt uses it): paths
# relative to the repository and no working directory in the hash, so the ci preset's build, pip's build and the
# default preset's share objects. -Werror (the ci preset's) is left out of the hash too, so that the default preset's
# objects are the ci build's; the ci stage therefore fails on any warning a cached object replays (see ci_build).
export CCACHE_BASEDIR="$repo" CCACHE_NOHASHDIR=1 CCACHE_IGNOREOPTIONS="-Werror"
# The compiler by the name CMake gives the presets: pip's build (scikit-build-core) would otherwise take Python's
# recorded compiler, x86_64-linux-gnu-g++, the same GCC under another name, and ccache hashes the name: every object
# of pip's build was a miss.
export CXX="${CXX:-c++}"
# Tests and fuzz harnesses run one per core: each test is its own process with its own scratch folder, and no test
# times itself (speed goals are the benchmarks'), so the cores only shorten the wait.
cores="$(nproc)"

all_stages=(build suite subgroups pip first-command sanitizers fuzz)
stages=("${@:-${all_stages[@]}}")
for s in "${stages[@]}"; do
  [[ " ${all_stages[*]} " == *" $s "* ]] || { echo "test.sh: no stage \"$s\" (have: ${all_stages[*]})" >&2; exit 2; }
done

# The ci preset: the engine, the command line, every test suite and the Python module, warnings as errors.
ci_build() {
  cmake --preset ci
  local log=build-ci/build.log
  cmake --build --preset ci 2>&1 | tee "$log"
  # A cached object replays its compiler's warnings but not a -Werror failure (the hash ignores -Werror, above).
  if grep -q "warning:" "$log"; then
    echo "test.sh: the build printed warnings (the ci preset treats them as errors):" >&2
    grep "warning:" "$log" | sort -u >&2
    return 1
  fi
}

# The Vulkan suite again at lavapipe's subgroup sizes 4 and 32 (the default width gives 8 on x86-64 with AVX): a
# kernel that assumes one subgroup size fails here without a GPU. The presets set LP_NATIVE_VECTOR_WIDTH and the
# size the suite must see (tests/backends/vulkan/test_subgroup_size.cpp checks it). At size 4 every transfer is also
# staged (SVA_VK_STAGING=1), as on a discrete GPU: uploads through staging buffers, and the host reads the kernels'
# results from host-cached copies, never from the device's BAR (gpu::add_mirror_read).
subgroups() {
  ctest --preset ci-subgroup-4 --parallel "$cores"
  ctest --preset ci-subgroup-32 --parallel "$cores"
}

# `pip install .` as a user runs it, into a fresh virtual environment, then the pytest suite against the installed
# package (not the build tree's module). The fresh environment gets the pinned tools of .venv (python/requirements.txt:
# NumPy, pytest, nanobind, scikit-build-core, ...) through a .pth file instead of a second download, so the step works
# offline; sva itself is in none of them. pip builds in its persistent folder (pyproject.toml: build-pip/) with the
# presets' flags, so the compiler cache has the objects of the ci build: only the extension's link is new work.
pip_install() {
  local venv="$repo/build-py/venv"
  rm -rf "$venv"
  /usr/bin/python3 -m venv "$venv"
  local own reuse
  own="$("$venv/bin/python" -c 'import sysconfig; print(sysconfig.get_paths()["purelib"])')"
  reuse="$("$repo/.venv/bin/python" -c 'import sysconfig; print(sysconfig.get_paths()["purelib"])')"
  echo "$reuse" >"$own/sva-test-reuse-dotvenv.pth"
  if "$venv/bin/python" -c 'import sva' 2>/dev/null; then
    echo "test.sh: the fresh environment imports sva before the install: is it installed in .venv?" >&2
    return 1
  fi
  "$venv/bin/python" -m pip install --disable-pip-version-check --no-build-isolation "$repo"
  # From a folder outside the repository, without PYTHONPATH: only the installed package can be imported.
  local scratch="$repo/build-py/pytest"
  rm -rf "$scratch" && mkdir -p "$scratch"
  (cd "$scratch" && env -u PYTHONPATH -u SVA_ASSETS MPLBACKEND=Agg SVA_TEST_SVA_BIN="$repo/build-ci/sva" \
    "$venv/bin/python" - "$venv" <<'PY'
import sys
import sva
where = sva.__file__
assert where.startswith(sys.argv[1] + "/"), f"sva imported from {where}, not from the fresh environment {sys.argv[1]}"
print(f"sva {getattr(sva, '__version__', '?')} from {where}")
PY
  )
  local rc=0
  (cd "$scratch" && env -u PYTHONPATH -u SVA_ASSETS MPLBACKEND=Agg SVA_TEST_SVA_BIN="$repo/build-ci/sva" \
    "$venv/bin/python" -m pytest -q -p no:cacheprovider "$repo/python/tests") || rc=$?
  if [ "$rc" = 5 ]; then
    echo "test.sh: pytest collected no tests from python/tests" >&2
  fi
  return "$rc"
}

# The README's first command after set-up: the default preset builds the command line only (objects from the
# compiler cache), and the demo runs every stage and prints its table, on the tiny scene: the default scene (paper3d,
# 11,000 readings) takes minutes to simulate and train, which the test command's budget has no room for. Its work
# folder is build/, so the run leaves no cached data where a user's `sva demo` would find it. The default preset is a
# unity build (CMakeLists.txt, SVA_UNITY_BUILD), which the suite's ci preset is not: its results must be the golden
# digests' too (an overload that one file's local helper took from another's in the same unit would show there).
first_command() {
  bash scripts/setup.sh --no-python && cmake --preset default || return 1
  local log=build/build.log
  cmake --build --preset default 2>&1 | tee "$log"
  [ "${PIPESTATUS[0]}" = 0 ] || return 1
  # A unit of 8 files shares their file-local names: one file's `using` reaches the next (a shadowed name, once). The
  # per-file presets cannot show that; a user's first build must print no warning.
  if grep -q "warning:" "$log"; then
    echo "test.sh: the default preset's unity build printed warnings:" >&2
    grep "warning:" "$log" | sort -u >&2
    return 1
  fi
  ./build/sva demo --scene tiny --work build/demo-tiny && python3 tests/determinism/golden.py build/sva build/golden-work
}

# AddressSanitizer and UBSan (the asan preset, leak detection on) over the suites that run in seconds; the slow
# suites under the sanitizers take far longer than the test command's budget (docs/reliability.md, Sanitizers).
sanitizers() {
  cmake --preset asan && cmake --build --preset asan-fast && ctest --preset asan-fast --parallel "$cores"
}

declare -A took
run_stage() {  # name, then the command
  local name="$1" t0=$SECONDS
  shift
  echo
  echo "==== test.sh: stage \"$name\" ($(date +%H:%M:%S))"
  if ! "$@"; then
    echo "==== test.sh: stage \"$name\" FAILED after $((SECONDS - t0)) s" >&2
    exit 1
  fi
  took[$name]=$((SECONDS - t0))
  echo "==== test.sh: stage \"$name\" passed in ${took[$name]} s"
}

start=$SECONDS
for s in "${stages[@]}"; do
  case "$s" in
    build) run_stage build ci_build ;;
    suite) run_stage suite ctest --preset ci --parallel "$cores" ;;
    subgroups) run_stage subgroups subgroups ;;
    pip) run_stage pip pip_install ;;
    first-command) run_stage first-command first_command ;;
    sanitizers) run_stage sanitizers sanitizers ;;
    fuzz) run_stage fuzz env FUZZ_PARALLEL="$cores" scripts/fuzz.sh 5 ;;
  esac
done
echo
echo "==== test.sh: every stage passed"
for s in "${stages[@]}"; do printf '  %-14s %5d s\n' "$s" "${took[$s]}"; done
printf '  %-14s %5d s\n' total $((SECONDS - start))
