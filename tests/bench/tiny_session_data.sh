# The tiny scene's data for the bench tools' smoke tests, the one home of it.
#   source tests/bench/tiny_session_data.sh

# A fresh WORK with the tiny scene (TRAIN and TEST readings per object, seed 1) in WORK/{train,test}.svad and its map,
# WORK/map.svam.
#   tiny_map SVA WORK TRAIN TEST
tiny_map() {
  local sva=$1 work=$2 train=$3 test=$4
  rm -rf "$work" && mkdir -p "$work"
  "$sva" --quiet simulate --scene tiny --out "$work" --train "$train" --test "$test" --seed 1 --threads 2
  "$sva" --quiet train --data "$work/train.svad" --out "$work/map.svam" --seed 1 --threads 2 > /dev/null
}

# For the tools that replay `sva eval` trials: tiny_map's with 20 and 12 readings, WORK/dense/test.svad (DENSE test
# readings per object, another seed) and WORK/random.csv (`sva eval --csv`, 2 trials of READINGS readings).
#   tiny_session_data SVA WORK DENSE READINGS
tiny_session_data() {
  local sva=$1 work=$2 dense=$3 readings=$4
  tiny_map "$sva" "$work" 20 12
  mkdir -p "$work/dense"
  "$sva" --quiet simulate --scene tiny --out "$work/dense" --train 1 --test "$dense" --seed 5 --threads 2
  "$sva" --quiet eval --map "$work/map.svam" --data "$work/test.svad" --trials 2 --max-readings "$readings" \
    --backend cpu --csv "$work/random.csv" > /dev/null
}
