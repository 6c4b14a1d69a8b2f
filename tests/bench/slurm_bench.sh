#!/usr/bin/env bash
# A library built locally and on a one-node Slurm cluster started here (root only): cold and warm
# times of each, and byte identity of every pack. Default: the demo library (after ./run demo).
#   tests/bench/slurm_bench.sh [LIBRARY.json] [ASSET_ROOT]
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
library=$(realpath "${1:-$root/out/library.json}")
assets=$(realpath "${2:-$root/..}")
bin=$root/build/bin work=$(mktemp -d /tmp/slurm_bench.XXXX)
trap '"$root/tests/scripts/slurm_cluster.sh" stop "$work/cluster"' EXIT
"$root/tests/scripts/slurm_cluster.sh" start "$work/cluster"
export SLURM_CONF=$work/cluster/slurm.conf
timed() { # timed LABEL command...: seconds on stdout
  local t0; t0=$(date +%s.%N)
  "${@:2}" || true
  printf '%-12s %6.1f s\n' "$1" "$(echo "$(date +%s.%N) - $t0" | bc)"
}
common=("$library" --asset-root "$assets" -q)
timed "local cold" "$bin/crowdbake" build "${common[@]}" -o "$work/local" --jobs "$(nproc)"
timed "local warm" "$bin/crowdbake" build "${common[@]}" -o "$work/local" --jobs "$(nproc)"
slurm=(--slurm --cpus-per-task 1 --jobs-per-task 4)
timed "slurm cold" "$bin/crowdbake" build "${common[@]}" -o "$work/farm" "${slurm[@]}"
timed "slurm warm" "$bin/crowdbake" build "${common[@]}" -o "$work/farm" "${slurm[@]}"
same=0 total=0
for p in "$work"/local/*.crowdpack; do
  total=$((total + 1))
  cmp -s "$p" "$work/farm/$(basename "$p")" && same=$((same + 1))
done
echo "packs byte-identical local vs Slurm: $same of $total"
rm -rf "$work/local" "$work/farm"
