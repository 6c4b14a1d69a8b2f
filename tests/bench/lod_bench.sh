#!/usr/bin/env bash
# LOD benchmark: ours (skinning-aware, 16 poses), ours pose-agnostic (bind pose only) and
# meshopt_simplify at 50/25/10/5% of the triangles, and the full mesh (0 by construction), on the
# models of lod_assets.sh: the rest-pose Hausdorff distance and its max and mean over every frame
# (% of the rest pose's diagonal, tests/bench/lod_distance.h), and the time of our sequence
# against meshopt's four calls (each the fastest of 5 runs; the 1M-triangle grids, bumpy and
# flat, once). Writes OUT/lod_bench.csv, OUT/lod_times.csv and, where node is installed, one
# SVG chart per asset and figure. Where gltfpack is installed (.tools, as ./run test installs
# it), its default and permissive (-sp) modes cut every asset at the same shares (-si SHARE -noq)
# and lod_bench measures them as drawn beside ours at their triangle counts: the last table, side
# by side. For speed against an earlier commit, see lod_speed.sh. Needs libmeshoptimizer-dev and
# libcgal-dev (then ./run build builds build/bin/lod_bench).
# Usage: tests/bench/lod_bench.sh [OUT]
set -euo pipefail
cd "$(dirname "$0")/../.."
out=${1:-out/bench}
[ -x build/bin/lod_bench ] || {
  echo "build/bin/lod_bench is missing: apt-get install libmeshoptimizer-dev libcgal-dev, then ./run build" >&2
  exit 1
}
source tests/bench/lod_assets.sh "$out"
gltfpack=.tools/node_modules/.bin/gltfpack
cuts=()
if [ -x "$gltfpack" ]; then
  mkdir -p "$out/lod/gltfpack"
  for a in "${assets[@]}"; do
    name=$(basename "${a%.*}")
    for share in 0.5 0.25 0.1 0.05; do
      "$gltfpack" -i "$a" -o "$out/lod/gltfpack/$name.default.$share.glb" -si $share -noq \
        >/dev/null 2>&1 || echo "gltfpack -si $share failed on $a" >&2
      "$gltfpack" -i "$a" -o "$out/lod/gltfpack/$name.permissive.$share.glb" -si $share -sp -noq \
        >/dev/null 2>&1 || echo "gltfpack -si $share -sp failed on $a" >&2
    done
  done
  cuts=(--cuts "$out/lod/gltfpack")
else
  echo "no $gltfpack (./run test installs it): no gltfpack columns" >&2
fi
build/bin/lod_bench "$out/lod_bench.csv" "$out/lod_times.csv" "${cuts[@]}" "${assets[@]}" 2>/dev/null
charts=yes
command -v node >/dev/null || { charts=no; echo "node not found: the tables, no SVG charts" >&2; }
for a in "${assets[@]}"; do
  [ $charts = yes ] || break
  name=$(basename "${a%.*}")
  for metric in rest_hausdorff_pct animated_max_hausdorff_pct animated_mean_hausdorff_pct; do
    grep -E "^(asset|$name)," "$out/lod_bench.csv" > "$out/lod/$name.csv"
    node tests/bench/chart.js "$out/lod_${name}_$metric.svg" "$name: $metric against triangles" \
      "triangles" "% of the bounding-box diagonal" "$out/lod/$name.csv" triangles $metric method
  done
done
python3 tests/bench/table.py "$out/lod_bench.csv"
python3 tests/bench/table.py "$out/lod_times.csv"
[ ${#cuts[@]} -eq 0 ] || python3 - "$out/lod_bench.csv" <<'PY'
import csv, sys
rows = {}
for r in csv.DictReader(open(sys.argv[1])):
    rows[(r["asset"], r["share"], r["method"])] = r
print("gltfpack against ours at its triangle counts: animated max Hausdorff, % of the diagonal")
print(f"{'asset':>28} {'share':>5} | {'gltfpack':>8} {'max':>7} {'ours':>7} | "
      f"{'-sp':>8} {'max':>7} {'ours':>7}")
for (asset, share, method), r in rows.items():
    if method != "gltfpack":
        continue
    cells = []
    for mode in ("", "_permissive"):
        g, o = rows.get((asset, share, "gltfpack" + mode)), rows.get((asset, share, "ours_at_gltfpack" + mode))
        cells.append(f"{g['triangles']:>8} {float(g['animated_max_hausdorff_pct']):7.3f} "
                     f"{float(o['animated_max_hausdorff_pct']):7.3f}" if g and o else " " * 24)
    print(f"{asset:>28} {share:>5} | {cells[0]} | {cells[1]}")
PY
