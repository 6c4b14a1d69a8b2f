#!/usr/bin/env bash
# LOD benchmark: ours (skinning-aware, 16 poses), ours pose-agnostic (bind pose only) and
# meshopt_simplify at 50/25/10/5% of the triangles, for the sample humanoid, CesiumMan, Fox (and
# every other shared asset): bind-pose and animated-max Hausdorff distance (% of the diagonal),
# and sequence time against meshopt's four calls. Writes OUT/lod_bench.csv, OUT/lod_times.csv and
# one SVG chart per asset. Needs libmeshoptimizer-dev and libcgal-dev (then ./run build builds
# build/bin/lod_bench). Usage: tests/bench/lod_bench.sh [OUT]
set -euo pipefail
cd "$(dirname "$0")/../.."
out=${1:-out/bench}
mkdir -p "$out/lod"
[ -x build/bin/lod_bench ] || {
  echo "build/bin/lod_bench is missing: apt-get install libmeshoptimizer-dev libcgal-dev, then ./run build" >&2
  exit 1
}
build/bin/crowdbake samples --no-cloth --out "$out/lod" > /dev/null
assets=("$out/lod/humanoid.glb")
for a in CesiumMan Fox RiggedFigure; do
  f=$(ls ../shared/assets/gltf/$a/*.glb 2>/dev/null | head -1 || true)
  [ -n "$f" ] && assets+=("$f")
done
build/bin/lod_bench "$out/lod_bench.csv" "$out/lod_times.csv" "${assets[@]}" 2>/dev/null
for a in "${assets[@]}"; do
  name=$(basename "$a" .glb)
  for metric in bind_hausdorff_pct animated_max_hausdorff_pct; do
    grep -E "^(asset|$name)," "$out/lod_bench.csv" > "$out/lod/$name.csv"
    node tests/bench/chart.js "$out/lod_${name}_$metric.svg" "$name: $metric against triangles" \
      "triangles" "% of the bounding-box diagonal" "$out/lod/$name.csv" triangles $metric method
  done
done
column -s, -t "$out/lod_bench.csv"
column -s, -t "$out/lod_times.csv"
