#!/usr/bin/env bash
# The same bake gives byte-identical packs at any thread count, from any directory and with or
# without a report.
set -euo pipefail
bin=$1 work=$2
rm -rf "$work" && mkdir -p "$work/a" "$work/b"
"$bin/crowdbake" samples --out "$work/a" >/dev/null
"$bin/crowdbake" samples --out "$work/b" >/dev/null
for f in humanoid.glb skirt_walk.pc2 skirt_run.pc2 skirt_stiff.pc2 noise.pc2; do
  cmp "$work/a/$f" "$work/b/$f"
done
echo "samples: the characters and the simulated cloth caches are identical on a second run"
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
# A report asks for figures (the impostor's accuracy), never for other bytes.
impostor=("$bin/crowdbake" impostor "$work/a/humanoid.glb" --clip walk --frames 2 --views 4x2 --texels 16 --quiet)
"${impostor[@]}" -o "$work/i1.crowdpack"
"${impostor[@]}" -o "$work/i2.crowdpack" --report "$work/i2.json"
cmp "$work/i1.crowdpack" "$work/i2.crowdpack"
grep -q '"between_views"' "$work/i2.json"
echo "impostor: identical with and without --report (which measures its accuracy)"
