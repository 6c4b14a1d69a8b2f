#!/usr/bin/env bash
# The three.js cross-check: every model of ../shared/assets/gltf, tests/data/blender (Blender
# exports: a scaled armature, rigid parts, 8 influences) and tests/data/gltfpack (gltfpack's
# quantized copies) is baked twice (crowdbake anim as float matrices, so frame times test the
# reading and float32 rounding alone, and crowdbake lod at the error budget's choice, whose
# vertices leave import order, and whose animation is joint tracks where they take fewer bytes) and, for every clip, three.js's pose of the glTF is compared vertex
# by vertex with crowdbake pose at every frame, every mid-frame and the bake's 64 random times
# (threejs_pose.mjs). Then the Blender crawler's variants as other exporters write files
# (gltf_variants.py: a Z-up or centimetre root, matrices, no inverse bind matrices, root motion,
# a skeleton root, loose weights, interleaved attributes, no indices, strips, byte weights,
# CUBICSPLINE keys, a sparse accessor, a joint scaled to zero, a .gltf with its buffer embedded
# or in a file whose name has a space) are baked as float matrices and compared the same way; the
# variants without indices and as strips also as lod packs (their corners welded back into
# shared vertices).
# Skips (skip.sh) where node or three (installed by ./run test into .tools) or the shared models
# are absent.
set -euo pipefail
. "$(dirname "$(realpath "$0")")/skip.sh"
bin=$1 root=$2 work=$3 assets=$4
need_node_tools "$root" three
three=$tools/three
[ -d "$assets" ] || skip_part "no shared models at $assets (../shared beside the checkout): the Blender exports only"
rm -rf "$work" && mkdir -p "$work"
status=0 models=0
check() { # check MODEL PACK REPORT
  node "$root/tests/scripts/threejs_pose.mjs" "$bin/crowdbake" "$three" "$@" "$work" || status=1
}
check_anim() { # check_anim MODEL NAME: the model baked as float matrices, then checked
  "$bin/crowdbake" anim "$1" -o "$work/$2.crowdpack" --report "$work/$2.json" -q --precision float \
    --store texture
  check "$1" "$work/$2.crowdpack" "$work/$2.json"
}
for model in "$assets"/*/*.glb "$assets"/*/*.gltf "$root"/tests/data/blender/*.glb \
  "$root"/tests/data/blender/*.gltf "$root"/tests/data/gltfpack/*.glb; do
  [ -f "$model" ] || continue
  name=$(basename "${model%.*}")
  check_anim "$model" "$name"
  "$bin/crowdbake" lod "$model" -o "$work/${name}_lod.crowdpack" --report "$work/${name}_lod.json" -q
  check "$model" "$work/${name}_lod.crowdpack" "$work/${name}_lod.json"
  models=$((models + 1))
done
[ $models -gt 0 ] || { echo "FAIL: no model found" >&2; exit 1; }
mkdir -p "$work/variants"
python3 "$root/tests/scripts/gltf_variants.py" "$root/tests/data/blender/crawler.glb" "$work/variants"
for model in "$work"/variants/*.glb "$work"/variants/*.gltf; do
  name=$(basename "${model%.*}")
  check_anim "$model" "$name"
  case $name in *_non_indexed | *_strips)
    "$bin/crowdbake" lod "$model" -o "$work/${name}_lod.crowdpack" \
      --report "$work/${name}_lod.json" -q
    check "$model" "$work/${name}_lod.crowdpack" "$work/${name}_lod.json" ;;
  esac
  models=$((models + 1))
done
[ $status = 0 ] && echo "three.js agrees with crowdbake pose on all $models models"
[ $status != 0 ] || end_skipped_parts
exit $status
