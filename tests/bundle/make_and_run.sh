#!/usr/bin/env bash
# ctest "bundle: ...": scripts/bundle.sh on this build into a temp folder, then,
# from another folder and with no help from the build tree, `sva --help` and a
# few tests through the bundle's run-tests.sh, so a broken bundle (a library
# left out, a path into the build tree) fails CI. The bundle's run-tests.sh runs
# the Catch2 executables only, never this test.
#   usage: make_and_run.sh SOURCE_DIR BUILD_DIR
set -euo pipefail
source_dir=$1 build_dir=$2
tmp=$(mktemp -d "${TMPDIR:-/tmp}/sva-bundle-test.XXXXXX")
trap 'rm -rf "$tmp"' EXIT
BUILD_DIR=$build_dir bash "$source_dir/scripts/bundle.sh" "$tmp/bundle"
cd "$tmp"
# The CLI loads (Embree, TBB, the Vulkan loader) and finds the bundled assets.
SVA_ASSETS="$tmp/bundle/assets" env -u LD_LIBRARY_PATH "$tmp/bundle/sva" --help >help.txt
head -n 3 help.txt
# Plain C++, the Vulkan loader with the embedded shaders, and the sva CLI
# simulating a built-in scene (Embree, TBB; the bundled sva and assets).
# The io area reads the bundled fuzz corpus, `sva view` the bundled viewer and three.js: none may be skipped.
LOG_DIR="$tmp/logs" env -u LD_LIBRARY_PATH "$tmp/bundle/run-tests.sh" io 'vulkan:*sva_div*' 'bench:*hash scatter*' \
  'sim:simulate: same seed*' 'eval:canvas*' 'eval:sva view writes*' | tee run.txt
tail -n 1 run.txt | grep -q ', 0 skipped$' || { echo "bundle: tests were skipped (something the bundle should carry)" >&2; exit 1; }
