#!/usr/bin/env bash
# The lab notebook (docs/notes/) is a record of runs, not run by the docs test: each of its sh, python and cpp blocks
# must carry an illustration marker (docs/docs-test.md), so that no block there looks runnable and goes untested.
#   tests/docs/check_notebook.sh PYTHON
set -euo pipefail
python=$1
here=$(dirname "$0")
root=$(cd "$here/../.." && pwd)
runs=$(for f in "$root"/docs/notes/*.md; do "$python" "$here/run_blocks.py" --list "$f"; done | grep ': runs$' || true)
if [[ -n $runs ]]; then
  echo "notebook blocks without an illustration marker (mark them, or move them to a page of the manual):" >&2
  echo "$runs" >&2
  exit 1
fi
echo "every block of docs/notes/ is marked as a record"
