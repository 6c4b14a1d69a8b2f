#!/usr/bin/env bash
# Player benchmark: the sample humanoid at 1k, 5k, 10k and 30k instances along the demo scene's
# camera path, instanced against naive (one draw per instance per sub-mesh) in the same binary
# and the same run. Prints a table and writes OUT/player_bench.csv.
# Usage: tests/bench/player_bench.sh [OUT] [FRAMES]   (after ./run demo, which bakes out/)
set -euo pipefail
cd "$(dirname "$0")/../.."
out=${1:-out/bench}
frames=${2:-4}
mkdir -p "$out"
[ -f out/humanoid.crowdpack ] || { echo "run ./run demo first (it bakes out/humanoid.crowdpack)" >&2; exit 1; }
csv=$out/player_bench.csv
echo "instances,path,frames,frame_ms,gpu_ms,draw_calls,triangles,renderer" > "$csv"
for n in 1000 5000 10000 30000; do
  for path in instanced naive; do
    flag=""; [ $path = naive ] && flag=--naive
    stats=$out/stats_${n}_$path.json
    # 2 s steps walk the 8 s camera path; 640x360 keeps llvmpipe's fill cost small.
    xvfb-run -a -s "-screen 0 640x480x24" build/bin/crowdplay samples/scenes/demo.json --headless \
      --frames "$frames" --step 2 --size 640x360 --instances $n $flag --stats "$stats" >/dev/null
    node -e '
      const s = require(process.argv[1]).summary;
      console.log([process.argv[2], process.argv[3], s.frames, s.frame_ms.toFixed(1), s.gpu_ms.toFixed(1),
                   s.draw_calls, s.triangles, JSON.stringify(s.renderer)].join(","));' "$(realpath "$stats")" $n $path >> "$csv"
  done
done
column -s, -t "$csv"
node -e '
  const rows = require("fs").readFileSync(process.argv[1], "utf8").trim().split("\n").slice(1).map(l => l.split(","));
  for (const n of ["1000", "5000", "10000", "30000"]) {
    const i = rows.find(r => r[0] === n && r[1] === "instanced"), v = rows.find(r => r[0] === n && r[1] === "naive");
    console.log(`${n}: naive/instanced draw calls ${(v[5] / i[5]).toFixed(0)}x, frame time ${(v[3] / i[3]).toFixed(2)}x, gpu time ${(v[4] / i[4]).toFixed(2)}x`);
  }' "$csv"
