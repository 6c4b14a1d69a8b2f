#!/usr/bin/env bash
# Budgeted LOD in the shape of the 2019 seed's Table 2: samples/scenes/crowd30k.json (30,000
# walkers, the humanoid with LOD) along its camera path, geometry only, at several triangle
# budgets N (none = full detail), then hybrid (impostors far away) at 2 M: frame time, GPU time,
# cull + select time, visible instances and triangles drawn per frame, all from one binary in
# one run. Then the CPU cost of culling + selection alone (lod_select_bench, best of 5 per
# frame), against building every visible instance's index data each frame.
# Writes OUT/budget_frames.csv, OUT/budget_table.csv, OUT/budget_*.svg, OUT/select_*.csv.
# Usage: tests/bench/budget_bench.sh [OUT] [FRAMES] [SIZE]   (after ./run demo)
set -euo pipefail
cd "$(dirname "$0")/../.."
out=${1:-out/bench}
frames=${2:-4}
size=${3:-640x360}
mkdir -p "$out"
[ -f out/humanoid.crowdpack ] || { echo "run ./run demo first (it bakes out/)" >&2; exit 1; }
scene=samples/scenes/crowd30k.json
step=$(node -e "console.log(18 / $frames)") # the camera path is 18 s long
csv=$out/budget_frames.csv
echo "path,budget,frame,time_s,frame_ms,gpu_ms,cull_select_ms,visible,impostors,triangles" > "$csv"
run_one() { # PATH BUDGET FLAGS
  local stats=$out/budget_$1_$2.json
  tests/scripts/xvfb.sh build/bin/crowdplay $scene --headless --frames "$frames" \
    --step "$step" --size "$size" --budget "$2" $3 --stats "$stats" > /dev/null
  node -e '
    const j = require(process.argv[1]);
    for (const f of j.frames)
      console.log([process.argv[2], process.argv[3], f.frame, f.time_s.toFixed(2), f.frame_ms.toFixed(1),
                   f.gpu_ms.toFixed(1), f.cull_select_ms.toFixed(3), f.visible, f.impostors, f.triangles].join(","));
  ' "$(realpath "$stats")" "$1" "$2" >> "$csv"
}
for n in 10000000 20000000 40000000 0; do run_one geometry $n --geometry; done
run_one hybrid 2000000 ""
node -e '
  const rows = require("fs").readFileSync(process.argv[1], "utf8").trim().split("\n").slice(1).map(l => l.split(","));
  const out = ["path,budget,frame_ms,gpu_ms,cull_select_ms,visible,triangles,max_triangles,within_budget"];
  const keys = [...new Set(rows.map(r => r[0] + "," + r[1]))];
  const mean = (a, i) => a.reduce((s, r) => s + +r[i], 0) / a.length;
  for (const k of keys) {
    const a = rows.filter(r => r[0] + "," + r[1] === k), budget = +k.split(",")[1];
    const max = Math.max(...a.map(r => +r[9]));
    out.push([k, mean(a, 4).toFixed(1), mean(a, 5).toFixed(1), mean(a, 6).toFixed(3),
              mean(a, 7).toFixed(0), mean(a, 9).toFixed(0), max, budget === 0 || max <= budget].join(","));
  }
  require("fs").writeFileSync(process.argv[2], out.join("\n") + "\n");
' "$csv" "$out/budget_table.csv"
python3 tests/bench/table.py "$out/budget_table.csv"
c="node tests/bench/chart.js"
$c "$out/budget_triangles.svg" "crowd30k: triangles drawn along the camera path" "time (s)" \
  "triangles" "$csv" time_s triangles budget
$c "$out/budget_frame_ms.svg" "crowd30k: frame time along the camera path (llvmpipe)" "time (s)" \
  "frame ms" "$csv" time_s frame_ms budget
for mode in geometry hybrid; do
  flag=""; [ $mode = geometry ] && flag=--geometry
  budget=2000000; [ $mode = geometry ] && budget=20000000
  build/bin/lod_select_bench $scene --frames 36 --budget $budget $flag > "$out/select_$mode.csv"
  tail -1 "$out/select_$mode.csv"
done
