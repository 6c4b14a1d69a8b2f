#!/usr/bin/env bash
# Impostor bake figures for the sample humanoid's walk (16 frames): accuracy and memory against
# the view count (8x4, 16x8, 32x8, 64x16 at 128 texels, mirrored) and against texels per view
# (32..256 at 32x8), charted as accuracy against bytes per frame (the memory/accuracy
# chart), and bake time at 1 and 2 threads (32x8, 128 texels, unmirrored: the speed target).
# Accuracy: frame 0 redrawn from the stored views against the true render, at the views and
# halfway between them, and popping (the largest per-pixel change a step of a slow orbit, in 8-bit
# levels, geometry against impostor). Writes OUT/impostor_views.csv, OUT/impostor_texels.csv, SVG charts.
# Usage: tests/bench/impostor_table.sh [OUT]   (after ./run build)
set -euo pipefail
cd "$(dirname "$0")/../.."
out=${1:-out/bench}
mkdir -p "$out/impostor"
bin=build/bin/crowdbake
$bin samples --no-cloth --out "$out/impostor" > /dev/null
glb=$out/impostor/humanoid.glb
row() { # REPORT -> CSV fields
  node -e '
    const r = require(process.argv[1]), a = r.accuracy;
    const f = v => +v.toPrecision(4);
    console.log([r.views, r.texels, r.bytes_per_frame, r.naive_bytes_per_frame, f(r.occupancy),
      f(a.at_views.iou_mean), f(a.at_views.normal_error_mean_deg), f(a.at_views.uv_error_mean),
      f(a.between_views.iou_mean), f(a.between_views.iou_min), f(a.between_views.normal_error_mean_deg),
      f(a.between_views.normal_error_max_deg), f(a.between_views.uv_error_mean),
      `${a.worst.azimuth_deg}/${a.worst.elevation_deg}`, f(a.popping.geometry_change_max),
      f(a.popping.impostor_change_max), f(r.job_s - a.time_s)].join(","));' "$(realpath "$1")"
}
header="views,texels,bytes_per_frame,naive_bytes_per_frame,occupancy,at_iou_mean,at_normal_mean_deg,at_uv_mean,between_iou_mean,between_iou_min,between_normal_mean_deg,between_normal_max_deg,between_uv_mean,worst_az/el_deg,pop_geometry_max,pop_impostor_max,bake_s"
echo "view_count,$header" > "$out/impostor_views.csv"
for v in 8x4 16x8 32x8 64x16; do
  $bin impostor "$glb" -o "$out/impostor/v.crowdpack" --clip walk --views $v --mirror --quiet \
    --report "$out/impostor/v.json"
  echo "$(( ${v%x*} * ${v#*x} )),$(row "$out/impostor/v.json")" >> "$out/impostor_views.csv"
done
echo "$header" > "$out/impostor_texels.csv"
for t in 32 64 128 256; do
  $bin impostor "$glb" -o "$out/impostor/t.crowdpack" --clip walk --texels $t --mirror --quiet \
    --report "$out/impostor/t.json"
  echo "$(row "$out/impostor/t.json")" >> "$out/impostor_texels.csv"
done
echo "threads,bake_s" > "$out/impostor_speed.csv"
for n in 1 2; do
  $bin impostor "$glb" -o "$out/impostor/s.crowdpack" --clip walk --threads $n --quiet \
    --report "$out/impostor/s.json"
  node -e 'const r = require(process.argv[1]);
    console.log(process.argv[2] + "," + (r.job_s - r.accuracy.time_s).toFixed(2))' \
    "$(realpath "$out/impostor/s.json")" $n >> "$out/impostor_speed.csv"
done
rm -f "$out"/impostor/*.crowdpack
c="node tests/bench/chart.js"
$c "$out/impostor_iou_vs_views.svg" "Silhouette IoU against the true render (walk, 128 texels)" \
  "views (azimuths x elevations)" "mean IoU" <(node -e '
    const l = require("fs").readFileSync(process.argv[1], "utf8").trim().split("\n");
    const h = l[0].split(","), i = h.indexOf("at_iou_mean"), j = h.indexOf("between_iou_mean");
    console.log("views,where,iou");
    for (const r of l.slice(1).map(x => x.split(","))) console.log(`${r[0]},at views,${r[i]}`);
    for (const r of l.slice(1).map(x => x.split(","))) console.log(`${r[0]},between views,${r[j]}`);' \
    "$(realpath "$out/impostor_views.csv")") views iou where log
$c "$out/impostor_normal_vs_views.svg" "Mean normal error between views (walk, 128 texels)" \
  "views (azimuths x elevations)" "degrees" "$out/impostor_views.csv" view_count between_normal_mean_deg "" log
$c "$out/impostor_memory_vs_texels.svg" "Bytes per frame against texels per view (32x8, mirrored)" \
  "texels per view" "MB per frame" <(node -e '
    const l = require("fs").readFileSync(process.argv[1], "utf8").trim().split("\n");
    console.log("texels,layout,mb");
    for (const r of l.slice(1).map(x => x.split(","))) console.log(`${r[1]},packed,${r[2] / 1e6}`);
    for (const r of l.slice(1).map(x => x.split(","))) console.log(`${r[1]},naive,${r[3] / 1e6}`);' \
    "$(realpath "$out/impostor_texels.csv")") texels mb layout log
# Accuracy against memory: both sweeps on one chart, x the bytes one frame holds on the GPU.
sweeps=$(mktemp)
node -e '
  const fs = require("fs");
  const read = p => { const l = fs.readFileSync(p, "utf8").trim().split("\n"); const h = l[0].split(",");
    return l.slice(1).map(x => { const r = x.split(","); return Object.fromEntries(h.map((k, i) => [k, r[i]])); }); };
  console.log("bytes_per_frame,sweep,between_iou_mean,between_normal_mean_deg");
  for (const r of read(process.argv[1])) console.log(`${r.bytes_per_frame},views (128 texels),${r.between_iou_mean},${r.between_normal_mean_deg}`);
  for (const r of read(process.argv[2])) console.log(`${r.bytes_per_frame},texels (32x8),${r.between_iou_mean},${r.between_normal_mean_deg}`);' \
  "$(realpath "$out/impostor_views.csv")" "$(realpath "$out/impostor_texels.csv")" > "$sweeps"
$c "$out/impostor_iou_vs_bytes.svg" "Between-view silhouette IoU against memory (walk, mirrored)" \
  "bytes per frame" "mean IoU" "$sweeps" bytes_per_frame between_iou_mean sweep log
$c "$out/impostor_normal_vs_bytes.svg" "Between-view normal error against memory (walk, mirrored)" \
  "bytes per frame" "degrees" "$sweeps" bytes_per_frame between_normal_mean_deg sweep log
rm -f "$sweeps"
for f in impostor_views impostor_texels impostor_speed; do echo "== $f"; python3 tests/bench/table.py "$out/$f.csv"; done
echo "charts: $out/impostor_iou_vs_views.svg $out/impostor_normal_vs_views.svg $out/impostor_memory_vs_texels.svg"
echo "        $out/impostor_iou_vs_bytes.svg $out/impostor_normal_vs_bytes.svg"
