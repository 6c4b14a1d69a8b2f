# The models the LOD benchmarks run on, in the array `assets` (sourced by lod_bench.sh and
# lod_speed.sh from the repository root): the sample humanoid, baked into $1/lod, every model of
# ../shared/assets/gltf, the Blender exports (tests/data/blender) and gltfpack's copies
# (tests/data/gltfpack).
mkdir -p "$1/lod"
build/bin/crowdbake samples --no-cloth --out "$1/lod" > /dev/null
assets=("$1/lod/humanoid.glb")
for f in ../shared/assets/gltf/*/*.glb ../shared/assets/gltf/*/*.gltf tests/data/blender/*.glb \
  tests/data/gltfpack/*.glb; do
  [ -f "$f" ] && assets+=("$f")
done
