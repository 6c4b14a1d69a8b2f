#!/usr/bin/env bash
# Cloth-loop bake figures on the sample caches (skirt_walk and skirt_stiff over walk, skirt_run
# over run, noise over walk; crowdbake cloth, default options): per cache the chosen seam's
# position and velocity jumps against the mean per-frame motion and velocity change, the verdict,
# blend, bytes, quantisation and both passes' times (OUT/cloth_loops.csv); every candidate's
# pass-1 and pass-2 scores (OUT/cloth_candidates.csv); SVG charts: pass 1's best seam per loop
# length, pass 1 at the chosen length over every start, pass 2's edge distance per candidate.
# Usage: tests/bench/cloth_table.sh [OUT]   (after ./run build)
set -euo pipefail
cd "$(dirname "$0")/../.."
out=${1:-out/bench}
s=$out/cloth
mkdir -p "$s"
bin=build/bin/crowdbake
$bin samples --out "$s" > /dev/null
for pair in skirt_walk:walk skirt_run:run skirt_stiff:walk noise:walk; do
  cache=${pair%:*} clip=${pair#*:}
  $bin cloth "$s/$cache.pc2" --fps 30 --body "$s/humanoid.glb" --outfit "$s/outfit_dress.glb" \
    --garment dress --clip "$clip" -o "$s/$cache.crowdpack" --report "$s/$cache.json" --quiet
done
node - "$(realpath "$out")" skirt_walk skirt_run skirt_stiff noise <<'JS'
const fs = require("fs");
const [out, ...caches] = process.argv.slice(2);
const f = v => (v === null ? "" : +(+v).toPrecision(4));
const loops = ["cache,clip,start,cycles,frames,acceptable,seam_position_jump_ratio," +
  "seam_velocity_jump_ratio,best_to_median,mean_motion_mm,mean_velocity_change_mm_s," +
  "blend_frames,pushed_vertices,pushed_max_mm,bytes,quant_max_mm,pass1_s,pass2_s,bake_s"];
const cands = ["cache,pass2_order,pass1_rank,start,cycles,pass1_distance,position_jump_mm," +
  "velocity_jump_mm_s,position_jump_ratio,velocity_jump_ratio,pass2_edge_px,pass2_px_per_view"];
const byCycles = ["cache,cycles,distance"], byStart = ["cache,start,distance"];
for (const c of caches) {
  const r = JSON.parse(fs.readFileSync(`${out}/cloth/${c}.json`, "utf8"));
  loops.push([c, r.clip, r.start, r.cycles, r.frames, r.acceptable, f(r.seam_position_jump_ratio),
    f(r.seam_velocity_jump_ratio), f(r.best_to_median), f(r.mean_motion_mm),
    f(r.mean_velocity_change_mm_s), r.blend_frames, r.pushed_out.vertices,
    f(r.pushed_out.max_mm), r.bytes, f(r.quantisation.max_mm), f(r.pass1_s), f(r.pass2_s),
    f(r.bake_s)].join(","));
  const ranked = r.candidates.map((k, i) => [k, i]).sort((a, b) => a[0].pass1_rank - b[0].pass1_rank);
  ranked.forEach(([k, i]) => cands.push([c, i, k.pass1_rank, k.start, k.cycles,
    f(k.pass1_distance), f(k.position_jump_mm), f(k.velocity_jump_mm_s),
    f(k.position_jump_ratio), f(k.velocity_jump_ratio), f(k.pass2_edge_px),
    k.pass2_edge_px_per_view.map(f).join(" ")].join(",")));
  for (const p of r.pass1.by_cycles) byCycles.push([c, p.cycles, p.distance].join(","));
  r.pass1.chosen_cycles_by_start.forEach((d, s) => {
    if (d !== null) byStart.push([c, s, d].join(","));
  });
}
const write = (name, rows) => fs.writeFileSync(`${out}/${name}`, rows.join("\n") + "\n");
write("cloth_loops.csv", loops);
write("cloth_candidates.csv", cands);
write("cloth_pass1_by_cycles.csv", byCycles);
write("cloth_pass1_by_start.csv", byStart);
JS
c="node tests/bench/chart.js"
$c "$out/cloth_pass1_by_length.svg" "Pass 1: the best seam of each loop length" \
  "loop length (clip cycles)" "filtered distance (mean per vertex, m^2)" \
  "$out/cloth_pass1_by_cycles.csv" cycles distance cache
$c "$out/cloth_pass1_by_start.svg" "Pass 1 at the chosen loop length, every start" \
  "start frame" "filtered distance (mean per vertex, m^2)" "$out/cloth_pass1_by_start.csv" \
  start distance cache
$c "$out/cloth_pass2.svg" "Pass 2: edge distance of pass 1's candidates (5 views)" \
  "pass-1 rank" "mean edge distance (px, summed over views)" "$out/cloth_candidates.csv" \
  pass1_rank pass2_edge_px cache
python3 tests/bench/table.py "$out/cloth_loops.csv"
echo "wrote $out/cloth_loops.csv, cloth_candidates.csv, cloth_pass1_*.csv and cloth_*.svg"
