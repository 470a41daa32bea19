#!/usr/bin/env bash
# Calibration families compared offline (docs/evaluation.md, "The temperature from a map of every object, and the top
# label"): the held-out sessions `sva train` learns from, on a map missing a fifth of the objects and on a map of
# every object, and sessions on the test set with the full map, every step's evidence written out
# (bench/calibration_study.cpp); then bench/calibration_study.py fits the temperature alone or with the top label on
# either kind of session, and the temperature on the test sessions themselves (its floor), and prints the ECE on the
# test sessions by reading range.
#   bench/calibration_study.sh DIR [SEED=1] [TEST_SESSIONS=200] [KNOWN_SESSIONS=60 [TEST_SEED=77]]
# KNOWN_SESSIONS above 60: calibration_study.py also fits each disjoint block of 60 (the fit's noise).
# DIR holds train.svad, test.svad and map.svam (trained with --seed SEED). BUILD_DIR (default build-ci); PYTHON (default
# python3) needs NumPy (the .venv of scripts/setup.sh has it).
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(dirname "$here")
dir=${1:?usage: bench/calibration_study.sh DIR [SEED] [TEST_SESSIONS]}
seed=${2:-1}
sessions=${3:-200}
known=${4:-60}
test_seed=${5:-77}
build=${BUILD_DIR:-$root/build-ci}
for f in train.svad test.svad map.svam; do [[ -f $dir/$f ]] || { echo "no $dir/$f" >&2; exit 1; }; done
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
lib() { find "$build" -name "lib$1.a" -not -path '*/package-test/*' | head -n 1; }
libs="$(lib sva_core) $(lib sva_io) $(lib sva_base)"
[[ -n ${libs// /} ]] || { echo "no libraries under $build (build first)" >&2; exit 1; }
c++ -std=c++20 -O2 -I"$root/host/include" -I"$root/host/src" -I"$root/host/base/include" -I"$root/host/io/include" \
  -I"$root/shaders/include" "$here/calibration_study.cpp" $libs $libs -ltbb -lvulkan -lpthread -o "$tmp/calibration_study"
"$tmp/calibration_study" "$dir/train.svad" "$dir/map.svam" "$dir/test.svad" "$seed" "$sessions" "$dir/study" "$known" \
  "$test_seed"
blocks=()
((known > 60)) && blocks=(--blocks 60)
"${PYTHON:-python3}" "$here/calibration_study.py" "$dir/study" "${blocks[@]}"
