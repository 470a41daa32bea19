#!/usr/bin/env bash
# The speed benchmark from a bundle (scripts/bundle.sh): simulates the built-in
# paper3d scene and trains its map (both cached in WORK), then
# `sva bench --map MAP --data TEST --json WORK/bench.json [args]` on all cores.
#
#   run-bench.sh [sva bench options]    e.g. --backend vulkan --trials 10 --readings 10,30,100
# Environment: WORK (default $PWD/paper3d), SIM_ARGS (extra `sva simulate` options,
#   e.g. "--train 100 --test 20" for a small quick dataset), TRAIN_ARGS (extra `sva train`
#   options), VK_DRIVER_FILES (the caller's ICD, kept), SVA_VK_VALIDATION (default 0),
#   SVA_THREADS (default: all cores).
# The dataset and map are made again when SIM_ARGS or TRAIN_ARGS change; delete WORK to
# start afresh. Exits non-zero when any step fails.
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/env.sh"
WORK=${WORK:-${PWD%/}/paper3d}
mkdir -p "$WORK"
WORK=$(cd "$WORK" && pwd)
sva=("$BUNDLE/sva")
# Progress lines only on a terminal; a log keeps the summaries and the figures.
[[ -t 2 ]] || sva+=(--quiet)
echo "== sva bench from $BUNDLE: work=$WORK threads=$SVA_THREADS ($SVA_NPROC cores)" \
     "VK_DRIVER_FILES=${VK_DRIVER_FILES:-(loader default)} SVA_VK_VALIDATION=$SVA_VK_VALIDATION"

# A step is redone when its inputs (the options it ran with) changed: the stamp
# file holds them and is written only after the step succeeded.
stale() { [[ ! -f $WORK/$1 || ! -f $WORK/.$1.args || $(<"$WORK/.$1.args") != "$2" ]]; }

sim_args=${SIM_ARGS:-}
if stale test.svad "$sim_args" || [[ ! -f $WORK/train.svad ]]; then
  echo "== sva simulate --scene paper3d $sim_args"
  rm -f "$WORK/.test.svad.args" "$WORK/.map.svam.args"
  # shellcheck disable=SC2086  # SIM_ARGS is a list of options
  "${sva[@]}" simulate --scene paper3d --out "$WORK" --threads "$SVA_THREADS" $sim_args
  printf '%s' "$sim_args" >"$WORK/.test.svad.args"
else
  echo "== dataset cached in $WORK (SIM_ARGS='$sim_args')"
fi

train_args=${TRAIN_ARGS:-}
if stale map.svam "$train_args"; then
  echo "== sva train $train_args"
  # shellcheck disable=SC2086  # TRAIN_ARGS is a list of options
  "${sva[@]}" train --data "$WORK/train.svad" --out "$WORK/map.svam" --threads "$SVA_THREADS" $train_args
  printf '%s' "$train_args" >"$WORK/.map.svam.args"
else
  echo "== map cached in $WORK (TRAIN_ARGS='$train_args')"
fi

echo "== sva bench --map $WORK/map.svam --data $WORK/test.svad --json $WORK/bench.json $*"
"${sva[@]}" bench --map "$WORK/map.svam" --data "$WORK/test.svad" --json "$WORK/bench.json" "$@"
echo "== figures in $WORK/bench.json"
