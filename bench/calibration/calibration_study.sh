#!/usr/bin/env bash
# Calibration families compared offline (docs/evaluation.md, "The temperature from a map of every object, and the top
# label"): the held-out sessions `sva train` learns from, on a map missing a fifth of the objects and on a map of every
# object, and sessions on the test set with the full map, every step's evidence written out
# (bench/calibration/calibration_study.cpp); then bench/calibration/calibration_study.py fits the temperature alone or
# with the top label on either kind of session, and the temperature on the test sessions themselves (its floor), and
# prints the ECE on the test sessions by reading range.
#   bench/calibration/calibration_study.sh DIR [SEED=1] [TEST_SESSIONS=200] [KNOWN_SESSIONS=60 [TEST_SEED=77]]
# KNOWN_SESSIONS above 60: calibration_study.py also fits each disjoint block of 60 (the fit's noise).
# DIR holds train.svad, test.svad and map.svam (trained with --seed SEED). BUILD_DIR (default build-ci); PYTHON (default
# python3) needs NumPy (the .venv of scripts/setup.sh has it).
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/../lib/common.sh"
dir=${1:?usage: bench/calibration/calibration_study.sh DIR [SEED] [TEST_SESSIONS]}
seed=${2:-1}
sessions=${3:-200}
known=${4:-60}
test_seed=${5:-77}
for f in train.svad test.svad map.svam; do [[ -f $dir/$f ]] || { echo "no $dir/$f" >&2; exit 1; }; done
calibration_study=$(bench_program calibration_study)
"$calibration_study" "$dir/train.svad" "$dir/map.svam" "$dir/test.svad" "$seed" "$sessions" "$dir/study" "$known" \
  "$test_seed"
blocks=()
((known > 60)) && blocks=(--blocks 60)
"${PYTHON:-python3}" "$ROOT/bench/calibration/calibration_study.py" "$dir/study" "${blocks[@]}"
