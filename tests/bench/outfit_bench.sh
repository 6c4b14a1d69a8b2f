#!/usr/bin/env bash
# Clothed crowds, tagged against naive (the WSCG 2009 clothed-crowds seed reports tagged about
# 20% faster): samples/scenes/clothed10k.json at 1k, 2.5k, 5k and 10k characters, each in one
# of the three sample outfits, drawn tagged (each outfit's visible sub-meshes through per-sub-mesh
# render queues) and naive (--whole-body: the whole body under the garments), geometry only (the
# pack also has walk impostors, which would take the far ones), same binary, same
# run. Frame time, GPU time, triangles and vertex shader invocations (as the driver counts them)
# per frame. Each pair runs REPEATS times, naive and tagged alternating, and the table keeps each
# one's fastest run (llvmpipe on a shared machine is noisy). Writes OUT/outfit_bench.csv.
# Usage: tests/bench/outfit_bench.sh [OUT] [FRAMES] [SIZE] [REPEATS]   (after ./run demo)
set -euo pipefail
cd "$(dirname "$0")/../.."
out=${1:-out/bench}
frames=${2:-4}
size=${3:-640x360}
repeats=${4:-2}
mkdir -p "$out"
[ -f out/library/clothed.crowdpack ] ||
  { echo "run ./run demo first (it builds out/library/clothed.crowdpack)" >&2; exit 1; }
csv=$out/outfit_bench.csv
echo "instances,method,run,frames,frame_ms,gpu_ms,cull_select_ms,draw_calls,triangles,vertices" > "$csv"
for n in 1000 2500 5000 10000; do
  for run in $(seq "$repeats"); do for method in naive tagged; do
    flag=""; [ $method = naive ] && flag=--whole-body
    stats=$out/outfit_${n}_$method.json
    xvfb-run -a -s "-screen 0 640x480x24" build/bin/crowdplay samples/scenes/clothed10k.json \
      --headless --frames "$frames" --size "$size" --instances $n $flag --geometry --stats "$stats" \
      >/dev/null
    node -e '
      const s = require(process.argv[1]).summary;
      console.log([process.argv[2], process.argv[3], process.argv[4], s.frames, s.frame_ms.toFixed(1), s.gpu_ms.toFixed(1),
                   s.cull_select_ms.toFixed(3), s.draw_calls, s.triangles, s.vertices ?? ""].join(","));' \
      "$(realpath "$stats")" $n $method $run >> "$csv"
  done; done
done
column -s, -t "$csv"
node -e '
  const rows = require("fs").readFileSync(process.argv[1], "utf8").trim().split("\n").slice(1).map(l => l.split(","));
  const best = (n, m) => rows.filter(r => r[0] === n && r[1] === m).reduce((a, b) => +a[4] <= +b[4] ? a : b);
  for (const n of [...new Set(rows.map(r => r[0]))]) {
    const t = best(n, "tagged"), v = best(n, "naive");
    console.log(`${n}: fastest frame ms tagged ${t[4]}, naive ${v[4]}: tagged/naive frame time ${(t[4] / v[4]).toFixed(3)}, ` +
                `gpu time ${(t[5] / v[5]).toFixed(3)}, triangles ${(t[8] / v[8]).toFixed(3)}` +
                (t[9] ? `, vertices ${(t[9] / v[9]).toFixed(3)}` : ""));
  }' "$csv"
