#!/usr/bin/env bash
# The sva test suite from a bundle (scripts/bundle.sh), with no cmake or ctest:
# every test case of every Catch2 executable in tests/ runs in its own process,
# as ctest runs them (a Vulkan test with no device ends its process with exit
# code 77: skipped), with a timeout.
#
#   run-tests.sh [AREA[:SPEC]...]     all areas by default; an area is an executable
#                                     tests/sva_tests_AREA, SPEC a Catch2 test spec
#                                     within it (e.g. vulkan:'*context*')
# Environment: VK_DRIVER_FILES (the caller's ICD, kept), SVA_VK_VALIDATION (default 0),
#   TEST_TIMEOUT (seconds per test, default 600), LOG_DIR (logs kept there; default a temp dir).
# Prints a line per executable and ends with "N passed, N failed, N skipped";
# exits 1 when a test failed, 2 on a usage error.
set -uo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/env.sh"

# Tests that need what a bundle does not carry; printed, never silently dropped.
declare -A excluded=(
  ["votes: the vote math header compiles as GLSL"]="needs glslangValidator and the source tree's shaders/include (a build-time check)"
)
echo "not in the bundle: package: install and consume (needs cmake and a C++ compiler), bundle: the bundle test itself"

areas=("$@")
if [[ ${#areas[@]} -eq 0 ]]; then
  for exe in "$BUNDLE"/tests/sva_tests_*; do areas+=("${exe##*/sva_tests_}"); done
fi
timeout_s=${TEST_TIMEOUT:-600}
LOG_DIR=${LOG_DIR:-$(mktemp -d "${TMPDIR:-/tmp}/sva-bundle-tests.XXXXXX")}
mkdir -p "$LOG_DIR/work" || exit 2
# The tests write their scratch files under TMPDIR; they run in a scratch folder.
cd "$LOG_DIR/work" || exit 2

# A test case name as a Catch2 test spec matching only itself (escaped as
# catch_discover_tests does for ctest).
spec_of() {
  local s=${1//\\/\\\\}
  s=${s//,/\\,}; s=${s//\[/\\[}; s=${s//\]/\\]}
  printf '%s' "$s"
}

echo "sva bundle $BUNDLE: VK_DRIVER_FILES=${VK_DRIVER_FILES:-(loader default)} SVA_VK_VALIDATION=$SVA_VK_VALIDATION, logs in $LOG_DIR"
total_pass=0 total_fail=0 total_skip=0 logs=0
failed_names=()
for arg in "${areas[@]}"; do
  area=${arg%%:*} filter=""
  [[ $arg == *:* ]] && filter=${arg#*:}
  exe="$BUNDLE/tests/sva_tests_$area"
  if [[ ! -x $exe ]]; then
    echo "no test executable for area '$area' (have: $(cd "$BUNDLE/tests" && ls | sed 's/^sva_tests_//' | tr '\n' ' '))" >&2
    exit 2
  fi
  # --list-test-names-only exits with the number of tests; the listing is what counts.
  mapfile -t names < <("$exe" ${filter:+"$filter"} --list-test-names-only | sed -e 's/\r$//' -e '/^$/d')
  if [[ ${#names[@]} -eq 0 ]]; then
    echo "$area: no tests${filter:+ match $filter}" >&2
    total_fail=$((total_fail + 1)); failed_names+=("$area: (no tests${filter:+ match $filter})")
    continue
  fi
  # An exclusion that names no test of its area is stale (the test moved or was renamed): it would let the test
  # run here and skip, so it is an error (unfiltered runs only; a filter may leave the test out).
  if [[ -z $filter ]]; then
    for ex in "${!excluded[@]}"; do
      [[ $ex == "$area: "* ]] || continue
      printf '%s\n' "${names[@]}" | grep -qxF -- "${ex#"$area: "}" && continue
      echo "  FAILED (stale exclusion in run-tests.sh): $ex names no test of $area"
      total_fail=$((total_fail + 1)); failed_names+=("$ex (stale exclusion)")
    done
  fi
  pass=0 fail=0 skip=0 t0=$SECONDS
  for name in "${names[@]}"; do
    full="$area: $name"
    if [[ -n ${excluded[$full]:-} ]]; then
      echo "  excluded: $full — ${excluded[$full]}"
      continue
    fi
    logs=$((logs + 1)) log="$LOG_DIR/$area.$logs.log"  # numbered across arguments: two specs of an area keep both
    timeout -k 10 "$timeout_s" "$exe" "$(spec_of "$name")" --reporter compact >"$log" 2>&1
    rc=$?
    # A spec that matched other than this one test case would hide a test.
    why="exit $rc"
    [[ $rc -eq 124 || $rc -eq 137 ]] && why="timeout after $timeout_s s"
    if [[ $rc -eq 0 ]] && ! grep -qE '^Passed 1 test case( with | \(no assertions)' "$log"; then
      rc=1 why="the spec did not run exactly this one test case"
    fi
    case $rc in
      0) pass=$((pass + 1)) ;;
      77) skip=$((skip + 1)); echo "  skipped: $full ($(grep -m1 -o 'SKIPPED: .*' "$log" | cut -c10-))" ;;
      *)
        fail=$((fail + 1)); failed_names+=("$full")
        echo "  FAILED ($why): $full"
        tail -n 40 "$log" | sed 's/^/    | /'
        ;;
    esac
  done
  echo "$area: $pass passed, $fail failed, $skip skipped ($((SECONDS - t0)) s)"
  total_pass=$((total_pass + pass)) total_fail=$((total_fail + fail)) total_skip=$((total_skip + skip))
done
if [[ ${#failed_names[@]} -gt 0 ]]; then
  echo "failed:"
  printf '  %s\n' "${failed_names[@]}"
fi
echo "$total_pass passed, $total_fail failed, $total_skip skipped"
[[ $total_fail -eq 0 ]]
