#!/usr/bin/env bash
# The same bake gives byte-identical packs at any thread count, from any directory and with or
# without a report: every bake, each run in two processes whose fresh memory glibc fills with
# different bytes (MALLOC_PERTURB_), so a byte written from memory never set shows.
set -euo pipefail
bin=$1 work=$2
fail() { echo "FAIL: $*" >&2; exit 1; }
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

# twice NAME ARGS...: `crowdbake ARGS -o` at 1 thread and at 3, memory perturbed otherwise.
twice() {
  local name=$1
  shift
  MALLOC_PERTURB_=85 "$bin/crowdbake" "$@" -o "$work/${name}_1.crowdpack" --threads 1 --quiet
  MALLOC_PERTURB_=170 "$bin/crowdbake" "$@" -o "$work/${name}_3.crowdpack" --threads 3 --quiet
  cmp "$work/${name}_1.crowdpack" "$work/${name}_3.crowdpack" || fail "$name differs"
  echo "$name: identical at 1 and 3 threads in two processes, memory perturbed"
}
a=$work/a
twice tracks anim "$a/humanoid.glb" --store tracks
twice lod lod "$a/humanoid.glb"
twice impostor impostor "$a/humanoid.glb" --clip walk --frames 2 --views 8x2 --texels 32 --mirror
twice outfits outfits "$a/humanoid.glb" --outfit "$a/outfit_dress.glb" \
  --outfit "$a/outfit_shirt_trousers.glb" --frame-step 8 --regions joint
twice cloth cloth "$a/skirt_stiff.pc2" --body "$a/humanoid.glb" --outfit "dress=$a/outfit_dress.glb" \
  --garment dress --clip walk --fps 30
twice terrain terrain "$a/village.glb" --cell 2
# A library build: its jobs in one worker and in three.
echo "{\"name\": \"walker\", \"body\": \"a/humanoid.glb\", \"lod\": {\"poses\": 2},
  \"impostor\": {\"clips\": [\"walk\"], \"frames\": 2, \"texels\": 32, \"views\": \"8x2\"}}" \
  > "$work/walker.json"
MALLOC_PERTURB_=85 "$bin/crowdbake" build "$work/walker.json" -o "$work/w1.crowdpack" --jobs 1 \
  --cache "$work/cache1" --quiet
MALLOC_PERTURB_=170 "$bin/crowdbake" build "$work/walker.json" -o "$work/w3.crowdpack" --jobs 3 \
  --cache "$work/cache3" --quiet
cmp "$work/w1.crowdpack" "$work/w3.crowdpack" || fail "the character build differs"
echo "build: identical at 1 and 3 workers in two processes, memory perturbed"
