#!/usr/bin/env bash
# The paper's raised-letters experiment (Sec 5.2, Fig. 5), simulated: five
# vowels, 192 readings each on a 4 x 4 grid x 12 orientations (one set to
# train, one to test), planar poses. 3 repetitions x 5 letters = 15 trials by
# default (TRIALS=150 for a smoother curve). Targets (paper): >= 90% accuracy
# by 30 readings, median inertial distance <= 1 mm by 20 readings.
# Env: as bench/accuracy/eval_paper3d.sh.
SCENE=letters2d
TRIALS="${TRIALS:-15}"
MAX_READINGS="${MAX_READINGS:-40}"
TARGETS="accuracy 30 >= 90
inertial_error_mm 20 <= 1"
source "$(dirname "${BASH_SOURCE[0]}")/eval_common.sh"
