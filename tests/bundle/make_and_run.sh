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
# The one-call device check of a GPU loan (run-device-check.sh), small: one area, a tiny paper3d, a short budget
# (90 s: the goals' benchmarks, the CPU reference's third among them, get at least 20 s each while that is left; the
# span models run whatever is left; the diagnostics after them mostly find no time left).
WORK="$tmp/p3d" AREAS=io SIM_ARGS="--train 30 --test 12" ARCHIVE="$tmp/check.tgz" env -u LD_LIBRARY_PATH \
  "$tmp/bundle/run-device-check.sh" "$tmp/check" 90 >check.txt 2>&1 || { cat check.txt; exit 1; }
tail -n 1 check.txt
for f in device.txt agreement.txt suite.txt bench-vulkan.txt bench-vulkan-light.txt bench-vulkan-top3.txt bench-vulkan-top3-prior.txt \
  bench-vulkan-batch-light.txt bench-vulkan-batch-cut.txt bench-vulkan-batch-warm.txt bench-vulkan-batch-untimed.txt bench-vulkan-batch-serial.txt estimate-span.txt update-span.txt \
  batch-span.txt bench-cpu.txt details.tgz; do
  [[ -s $tmp/check/$f ]] || { cat check.txt; echo "bundle: run-device-check.sh wrote no $f" >&2; exit 1; }
done
# ARCHIVE: the same files in one archive, under the folder's name.
# Listed once: `tar | grep -q` under pipefail fails when grep's early exit cuts tar's listing short (SIGPIPE).
listing=$(tar -tzf "$tmp/check.tgz")
grep -qx 'check/estimate-span.txt' <<< "$listing" && grep -qx 'check/update-span.txt' <<< "$listing" &&
  grep -qx 'check/details.tgz' <<< "$listing" || { echo "$listing"; echo "bundle: ARCHIVE lacks the check's files" >&2; exit 1; }
grep -q '^io: [0-9]* passed, 0 failed, 0 skipped' "$tmp/check/suite.txt" || { echo "bundle: the device check's suite failed" >&2; exit 1; }
# The summary against issue 52's goals reads this check's own files (scripts/device-check-summary.py).
python3 "$source_dir/scripts/device-check-summary.py" "$tmp/check.tgz" >summary.md ||
  { cat summary.md; echo "bundle: device-check-summary.py failed on the check" >&2; exit 1; }
grep -q '^- suite: [1-9][0-9]* passed, 0 failed' summary.md && grep -q '^## One session' summary.md &&
  grep -q '^## Batches' summary.md ||
  { cat summary.md; echo "bundle: the check's summary lacks its figures" >&2; exit 1; }
grep -q '^cpu  *100 ' "$tmp/check/bench-cpu.txt" || { echo "bundle: the device check's CPU benchmark did not finish" >&2; exit 1; }
# One session's estimate beside its modelled critical path, from the bundled bench program, at 30 and 100 readings.
[[ $(grep -cE '^1 sessions at (30|100) readings, .*digest [0-9a-f]{16}$' "$tmp/check/estimate-span.txt") == 2 &&
  $(grep -c '^one session alone, its loops split for ' "$tmp/check/estimate-span.txt") == 2 ]] ||
  { cat "$tmp/check/estimate-span.txt"; echo "bundle: the device check's estimate span is missing" >&2; exit 1; }
# One session's update under the span probe, split for 16 and for 8 threads, at 10, 30 and 100 readings.
[[ $(grep -cE '^update at reading +(10|30|100) under a span probe, its loops split for (16|8) threads: ' \
  "$tmp/check/update-span.txt") == 6 ]] ||
  { cat "$tmp/check/update-span.txt"; echo "bundle: the device check's update span is missing" >&2; exit 1; }
# 64 sessions to 10 readings on 16 and on 2 threads, each measured and under the span probe, the same answers.
[[ $(grep -cE '^64 sessions x 10 readings, top 1, full, (16|2) thread\(s\): .*digest [0-9a-f]{16}$' "$tmp/check/batch-span.txt") == 2 &&
  $(grep -cE '^under a span probe, its loops split for (16|2) thread\(s\), .* as scheduled \(a model\)$' \
    "$tmp/check/batch-span.txt") == 2 &&
  $(grep -Eo 'digest [0-9a-f]{16}' "$tmp/check/batch-span.txt" | sort -u | wc -l) == 1 ]] ||
  { cat "$tmp/check/batch-span.txt"; echo "bundle: the device check's batch span is missing" >&2; exit 1; }
# A driver that does not load fails the check, which then checked nothing, and device.txt names the file.
[[ -f $tmp/bundle/glvnd/libEGL.so.1 && -f $tmp/bundle/glvnd/libGLdispatch.so.0 ]] ||
  { echo "bundle: no libglvnd (libEGL.so.1, libGLdispatch.so.0) for NVIDIA's driver" >&2; exit 1; }
# env.sh reaches the bundle's libglvnd only on a machine without libEGL.so.1: one whose ldconfig lists nothing here.
lib_path() { env -u LD_LIBRARY_PATH PATH="$1" bash -c 'source "$0/env.sh" >/dev/null; echo "${LD_LIBRARY_PATH:-}"' \
  "$tmp/bundle"; }
mkdir -p "$tmp/no-egl" && printf '#!/bin/sh\nexit 0\n' >"$tmp/no-egl/ldconfig" && chmod +x "$tmp/no-egl/ldconfig"
[[ $(lib_path "$tmp/no-egl:$PATH") == "$tmp/bundle/glvnd" && $(lib_path "$PATH") != *glvnd* ]] ||
  { echo "bundle: env.sh put libglvnd on LD_LIBRARY_PATH where it should not, or not where it should" >&2; exit 1; }
if VK_DRIVER_FILES="$tmp/no_icd.json" WORK="$tmp/p3d" AREAS=io env -u LD_LIBRARY_PATH \
  "$tmp/bundle/run-device-check.sh" "$tmp/check2" 60 >check2.txt 2>&1; then
  cat check2.txt; echo "bundle: the device check passed with no Vulkan driver" >&2; exit 1
fi
grep -q "^driver file $tmp/no_icd.json: missing" "$tmp/check2/device.txt" &&
  grep -q '^no Vulkan device: the agreement tests were skipped' "$tmp/check2/agreement.txt" &&
  grep -q '(failed: exit 1)' "$tmp/check2/bench-vulkan.txt" ||
  { cat check2.txt "$tmp/check2/device.txt"; echo "bundle: the check without a driver did not say why" >&2; exit 1; }
