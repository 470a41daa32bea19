#!/usr/bin/env bash
# tests/docs/check_paths.py: the repository's docs name only paths that exist, and a stale path is caught by name
# (a document of its own with one moved folder, one placeholder and one user file, which must not count).
#   tests/docs/check_paths_test.sh PYTHON WORK
set -euo pipefail
python=$1 work=$2
here=$(dirname "$0")
out=$("$python" "$here/check_paths.py")
echo "$out"
# Every page is read, the lab notebook's (docs/notes/) included: README.md and docs/**/*.md.
pages=$(( 1 + $(find "$here/../../docs" -name '*.md' | wc -l) ))
grep -q "in $pages document(s)" <<< "$out" || { echo "not every page was read ($pages expected): $out" >&2; exit 1; }
rm -rf "$work" && mkdir -p "$work"
printf '%s\n' '# A page' 'The votes live in `host/src/vulkan/` and `votes/pose_space.*`;' \
  'a run writes `OUT_DIR/run-tests.sh` and `la/map.svam`.' '```sh' 'cat host/src/nowhere.cpp' '```' > "$work/page.md"
if out=$("$python" "$here/check_paths.py" "$work/page.md"); then echo "a stale path was not caught: $out" >&2; exit 1; fi
grep -q "page.md:2: \`host/src/vulkan/\` names no file or folder" <<< "$out" || { echo "not named: $out" >&2; exit 1; }
[[ $(grep -c "names no file" <<< "$out") == 1 ]] || { echo "more than the one stale path: $out" >&2; exit 1; }
