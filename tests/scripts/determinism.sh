#!/usr/bin/env bash
# The same bake gives byte-identical packs at any thread count and from any directory.
set -euo pipefail
bin=$1 work=$2
rm -rf "$work" && mkdir -p "$work/a" "$work/b"
"$bin/crowdbake" samples --out "$work/a" >/dev/null
"$bin/crowdbake" samples --out "$work/b" >/dev/null
cmp "$work/a/humanoid.glb" "$work/b/humanoid.glb"
for precision in float half qts; do
  for threads in 1 2 5; do
    "$bin/crowdbake" anim "$work/a/humanoid.glb" -o "$work/t$threads.crowdpack" --threads $threads --precision $precision --quiet
  done
  (cd "$work/b" && "$bin/crowdbake" anim humanoid.glb -o ../elsewhere.crowdpack --threads 2 --precision $precision --quiet)
  cmp "$work/t1.crowdpack" "$work/t2.crowdpack"
  cmp "$work/t1.crowdpack" "$work/t5.crowdpack"
  cmp "$work/t1.crowdpack" "$work/elsewhere.crowdpack"
  echo "$precision: identical at 1, 2 and 5 threads and from another directory"
done
