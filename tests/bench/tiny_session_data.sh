# The tiny scene's data for the smoke tests of the bench tools that replay `sva eval` trials: WORK/{train,test}.svad,
# WORK/map.svam, WORK/dense/test.svad (DENSE test readings per object, another seed) and WORK/random.csv (`sva eval
# --csv`, 2 trials of READINGS readings).
#   source tests/bench/tiny_session_data.sh && tiny_session_data SVA WORK DENSE READINGS
tiny_session_data() {
  local sva=$1 work=$2 dense=$3 readings=$4
  rm -rf "$work" && mkdir -p "$work/dense"
  "$sva" --quiet simulate --scene tiny --out "$work" --train 20 --test 12 --seed 1 --threads 2
  "$sva" --quiet simulate --scene tiny --out "$work/dense" --train 1 --test "$dense" --seed 5 --threads 2
  "$sva" --quiet train --data "$work/train.svad" --out "$work/map.svam" --seed 1 --threads 2 > /dev/null
  "$sva" --quiet eval --map "$work/map.svam" --data "$work/test.svad" --trials 2 --max-readings "$readings" \
    --backend cpu --csv "$work/random.csv" > /dev/null
}
