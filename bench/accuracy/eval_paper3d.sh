#!/usr/bin/env bash
# The paper's 3D experiment (Sec 5.1, Fig. 4): 10 objects, 1000 training and
# 100 test readings each, 3 repetitions x 10 objects = 30 trials of 30
# readings, SVA and the appearance-only baseline. Targets (paper): 100%
# accuracy by 13 readings, median translation error <= 4 mm at 30 readings.
# Env: SVA (binary), OUT (work dir, reused: delete it to re-simulate),
# TRIALS, MAX_READINGS, SEED, THREADS, BACKEND, SIM_ARGS (e.g. "--train 300").
SCENE=paper3d
TRIALS="${TRIALS:-30}"
MAX_READINGS="${MAX_READINGS:-30}"
TARGETS="accuracy 13 >= 100
translation_error_mm 30 <= 4"
source "$(dirname "${BASH_SOURCE[0]}")/eval_common.sh"
