#!/usr/bin/env bash
# LOD benchmark: ours (skinning-aware, 16 poses), ours pose-agnostic (bind pose only) and
# meshopt_simplify at 50/25/10/5% of the triangles, and the full mesh (0 by construction), on the
# models of lod_assets.sh: the rest-pose Hausdorff distance and its max and mean over every frame
# (% of the rest pose's diagonal, tests/bench/lod_distance.h), and the time of our sequence
# against meshopt's four calls (each the fastest of 5 runs; the 1M-triangle grids, bumpy and
# flat, once). Writes OUT/lod_bench.csv, OUT/lod_times.csv and, where node is installed, one
# SVG chart per asset and figure. For speed against an earlier commit, see lod_speed.sh. Needs
# libmeshoptimizer-dev and libcgal-dev (then ./run build builds build/bin/lod_bench).
# Usage: tests/bench/lod_bench.sh [OUT]
set -euo pipefail
cd "$(dirname "$0")/../.."
out=${1:-out/bench}
[ -x build/bin/lod_bench ] || {
  echo "build/bin/lod_bench is missing: apt-get install libmeshoptimizer-dev libcgal-dev, then ./run build" >&2
  exit 1
}
source tests/bench/lod_assets.sh "$out"
build/bin/lod_bench "$out/lod_bench.csv" "$out/lod_times.csv" "${assets[@]}" 2>/dev/null
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
