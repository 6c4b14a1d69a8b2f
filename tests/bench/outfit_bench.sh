#!/usr/bin/env bash
# Clothed crowds, tagged against naive (the WSCG 2009 clothed-crowds seed reports tagged about
# 20% faster): samples/scenes/clothed10k.json at 1k, 2.5k, 5k and 10k characters, each in one
# of the three sample outfits, drawn tagged (each outfit's visible sub-meshes through per-sub-mesh
# render queues) and naive (--whole-body: the whole body under the garments), same binary, same
# run. Frame time, GPU time, triangles and vertex shader invocations (as the driver counts them)
# per frame. Writes OUT/outfit_bench.csv.
# Usage: tests/bench/outfit_bench.sh [OUT] [FRAMES] [SIZE]   (after ./run demo)
set -euo pipefail
cd "$(dirname "$0")/../.."
out=${1:-out/bench}
frames=${2:-4}
size=${3:-640x360}
mkdir -p "$out"
[ -f out/clothed.crowdpack ] || { echo "run ./run demo first (it bakes out/clothed.crowdpack)" >&2; exit 1; }
csv=$out/outfit_bench.csv
echo "instances,method,frames,frame_ms,gpu_ms,cull_select_ms,draw_calls,triangles,vertices" > "$csv"
for n in 1000 2500 5000 10000; do
  for method in tagged naive; do
    flag=""; [ $method = naive ] && flag=--whole-body
    stats=$out/outfit_${n}_$method.json
    xvfb-run -a -s "-screen 0 640x480x24" build/bin/crowdplay samples/scenes/clothed10k.json \
      --headless --frames "$frames" --size "$size" --instances $n $flag --stats "$stats" >/dev/null
    node -e '
      const s = require(process.argv[1]).summary;
      console.log([process.argv[2], process.argv[3], s.frames, s.frame_ms.toFixed(1), s.gpu_ms.toFixed(1),
                   s.cull_select_ms.toFixed(3), s.draw_calls, s.triangles, s.vertices ?? ""].join(","));' \
      "$(realpath "$stats")" $n $method >> "$csv"
  done
done
column -s, -t "$csv"
node -e '
  const rows = require("fs").readFileSync(process.argv[1], "utf8").trim().split("\n").slice(1).map(l => l.split(","));
  for (const n of [...new Set(rows.map(r => r[0]))]) {
    const t = rows.find(r => r[0] === n && r[1] === "tagged"), v = rows.find(r => r[0] === n && r[1] === "naive");
    console.log(`${n}: tagged/naive frame time ${(t[3] / v[3]).toFixed(3)}, gpu time ${(t[4] / v[4]).toFixed(3)}, ` +
                `triangles ${(t[7] / v[7]).toFixed(3)}` + (t[8] ? `, vertices ${(t[8] / v[8]).toFixed(3)}` : ""));
  }' "$csv"
