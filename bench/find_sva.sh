# Sourced by the bench scripts: sets ROOT and SVA (the sva binary: $SVA if set,
# else the first one built in the usual build directories), or exits 2.
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
if [[ -z "${SVA:-}" ]]; then
  for c in "$ROOT/build/sva" "$ROOT/build-ci/sva" "$ROOT/build-sim/sva" "$ROOT/build-eval/sva" "$ROOT/build/host/cli/sva"; do
    [[ -x "$c" ]] && SVA="$c" && break
  done
fi
[[ -x "${SVA:-}" ]] || { echo "bench: no sva binary; build it or set SVA=/path/to/sva" >&2; exit 2; }
