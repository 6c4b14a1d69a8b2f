#!/usr/bin/env bash
# The checks that want a real GPU, in one run, with no display (crowdplay --headless and the GPU
# test make their context through EGL): the shader against its CPU mirror
# (crowd_gpu_skinning_tests), the player benchmark at two sizes (player_bench.sh), the big scenes
# hybrid against geometry only, and clothed crowds tagged against naive (outfit_bench.sh). Every
# ratio compares runs of the same binary on the same GPU in this run.
# Usage: tests/bench/gpu_check.sh [OUT] [FRAMES]   (after ./run demo, which bakes out/; the GPU
#   test writes the samples itself, or reads them from $CROWD_SAMPLES)
set -euo pipefail
cd "$(dirname "$0")/../.."
out=$(realpath -m "${1:-out/gpu_check}")
frames=${2:-16}
mkdir -p "$out"
play=build/bin/crowdplay
echo "== the shader against its CPU mirror"
build/bin/crowd_gpu_skinning_tests 2>&1 | grep -v "^\[ *\(OK\|RUN\) " | tee "$out/gpu_skinning.log"
for size in 640x360 1920x1080; do
  echo "== player benchmark, $size"
  tests/bench/player_bench.sh "$out/player_$size" "$frames" "$size" | tail -14
done
echo "== scenes at 1920x1080: hybrid, then geometry only"
for scene in crowd10k crowd30k clothed10k library_mix; do
  for mode in "" --geometry; do
    printf '%-12s %-10s ' $scene "${mode:-hybrid}"
    $play samples/scenes/$scene.json --headless --frames "$frames" --size 1920x1080 $mode \
      --stats "$out/$scene$mode.json"
  done
done
echo "== clothed crowds at 1920x1080, geometry only: tagged against naive (--whole-body)"
tests/bench/outfit_bench.sh "$out/outfit" "$frames" 1920x1080 1 | tail -4
