#!/usr/bin/env bash
# Hybrid rendering benchmark: samples/scenes/crowd10k.json at 10k and 30k walkers along its camera
# path, instanced geometry only (--geometry) against hybrid (impostors past the 1:1 distance), in
# the same binary and the same run. Prints a table and writes OUT/hybrid_bench.csv.
# Usage: tests/bench/hybrid_bench.sh [OUT] [FRAMES] [WxH]   (after ./run demo, which bakes out/)
# BASELINE=DIR: another checkout (the previous release), built and with its own out/ from its
# ./run demo; its hybrid path runs right after this one's, the same arguments, and the ratio is
# printed. PATHS=hybrid skips the geometry-only runs (over 30 minutes at 10k on llvmpipe).
set -euo pipefail
cd "$(dirname "$0")/../.."
here=$PWD
out=$(realpath -m "${1:-out/bench}")
frames=${2:-4}
size=${3:-960x540}
mkdir -p "$out"
for f in out/humanoid.crowdpack out/humanoid_walk.impostor.crowdpack; do
  [ -f $f ] || { echo "run ./run demo first (it bakes $f)" >&2; exit 1; }
  [ -z "${BASELINE:-}" ] || [ -f "$BASELINE/$f" ] ||
    { echo "BASELINE: run ./run demo in $BASELINE first (it bakes $f)" >&2; exit 1; }
done
csv=$out/hybrid_bench.csv
echo "instances,path,frames,frame_ms,gpu_ms,draw_calls,impostors,triangles,renderer" > "$csv"
step=$(node -e "console.log(12 / $frames)") # the path is 12 s long
runs="${PATHS:-geometry hybrid}"
[ -n "${BASELINE:-}" ] && runs="$runs baseline"
# One untimed frame per binary first: after a rebuild, Mesa's shader cache is cold and llvmpipe
# compiles the shaders during the first timed frame (about 80 ms of it at 10k).
for tree in "$here" ${BASELINE:+"$(realpath "$BASELINE")"}; do
  (cd "$tree" && "$here/tests/scripts/xvfb.sh" build/bin/crowdplay \
    samples/scenes/crowd10k.json --headless --frames 1 --size "$size" --instances 1000 >/dev/null)
done
for n in 10000 30000; do
  for path in $runs; do
    flag=""; [ $path = geometry ] && flag=--geometry
    tree=$here; [ $path = baseline ] && tree=$(realpath "$BASELINE")
    stats=$out/hybrid_${n}_$path.json
    (cd "$tree" && "$here/tests/scripts/xvfb.sh" build/bin/crowdplay \
      samples/scenes/crowd10k.json --headless --frames "$frames" --step "$step" --size "$size" \
      --instances $n $flag --stats "$stats" >/dev/null)
    node -e '
      const s = require(process.argv[1]).summary;
      console.log([process.argv[2], process.argv[3], s.frames, s.frame_ms.toFixed(1), s.gpu_ms.toFixed(1),
                   s.draw_calls, s.impostors.toFixed(0), s.triangles.toFixed(0), JSON.stringify(s.renderer)].join(","));' \
      "$(realpath "$stats")" $n $path >> "$csv"
  done
done
python3 tests/bench/table.py "$csv"
node -e '
  const rows = require("fs").readFileSync(process.argv[1], "utf8").trim().split("\n").slice(1).map(l => l.split(","));
  for (const n of ["10000", "30000"]) {
    const [g, h, b] = ["geometry", "hybrid", "baseline"].map(p => rows.find(r => r[0] === n && r[1] === p));
    if (g && h)
      console.log(`${n}: geometry/hybrid frame time ${(g[3] / h[3]).toFixed(1)}x, gpu time ${(g[4] / h[4]).toFixed(1)}x, triangles ${(g[7] / h[7]).toFixed(0)}x fewer`);
    if (b && h)
      console.log(`${n}: hybrid frame time ${(h[3] / b[3]).toFixed(2)}x the baseline (${h[3]} against ${b[3]} ms)`);
  }' "$csv"
