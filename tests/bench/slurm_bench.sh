#!/usr/bin/env bash
# A library built locally and on a one-node Slurm cluster started here (root only): cold and warm
# times of each, and byte identity of every pack. Default: the demo library (after ./run demo).
#   tests/bench/slurm_bench.sh [LIBRARY.json] [ASSET_ROOT]
# MAX_ARRAY_SIZE (the cluster's MaxArraySize, default 100000), JOBS_PER_TASK (default 4), CPUS
# (the node's, default the cores: more lets latency-bound tiny tasks overlap) and BIN (a copy of
# build/bin, so that the tree can be rebuilt meanwhile), e.g. 5,000 small jobs past Slurm's
# default MaxArraySize:
#   python3 tests/bench/farm_library.py 2500 /tmp/q s --tiny tests/fuzz/seed_quad.gltf
#   CPUS=32 MAX_ARRAY_SIZE=1001 JOBS_PER_TASK=2 tests/bench/slurm_bench.sh /tmp/q/library.json /tmp/q
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
library=$(realpath "${1:-$root/out/library.json}")
assets=$(realpath "${2:-$root/..}")
bin=${BIN:-$root/build/bin} work=$(mktemp -d /tmp/slurm_bench.XXXX)
trap '"$root/tests/scripts/slurm_cluster.sh" stop "$work/cluster"' EXIT
"$root/tests/scripts/slurm_cluster.sh" start "$work/cluster"
echo "MaxArraySize: $(SLURM_CONF=$work/cluster/slurm.conf scontrol show config | sed -n 's/^MaxArraySize *= *//p')"
export SLURM_CONF=$work/cluster/slurm.conf
timed() { # timed LABEL command...: seconds on stdout
  local t0; t0=$(date +%s.%N)
  "${@:2}" || true
  printf '%-12s %6.1f s\n' "$1" "$(echo "$(date +%s.%N) - $t0" | bc)"
}
common=("$library" --asset-root "$assets" -q)
timed "local cold" "$bin/crowdbake" build "${common[@]}" -o "$work/local" --jobs "$(nproc)"
timed "local warm" "$bin/crowdbake" build "${common[@]}" -o "$work/local" --jobs "$(nproc)"
slurm=(--slurm --cpus-per-task 1 --jobs-per-task "${JOBS_PER_TASK:-4}")
timed "slurm cold" "$bin/crowdbake" build "${common[@]}" -o "$work/farm" "${slurm[@]}"
timed "slurm warm" "$bin/crowdbake" build "${common[@]}" -o "$work/farm" "${slurm[@]}"
echo "job arrays: $(cd "$work/farm/.slurm" && ls stage*.sbatch | tr '\n' ' ')"
same=0 total=0
for p in "$work"/local/*.crowdpack; do
  total=$((total + 1))
  cmp -s "$p" "$work/farm/$(basename "$p")" && same=$((same + 1))
done
echo "packs byte-identical local vs Slurm: $same of $total"
rm -rf "$work/local" "$work/farm"
