#!/usr/bin/env bash
# Inputs as web pipelines write them: gltfpack (npm, pinned by ./run) copies of every shared model
# and the sample humanoid, plain, with -c (EXT_meshopt_compression) and with -cc (its filters:
# octahedral normals, quaternion rotations, exponential floats). The -c copy bakes to a pack that
# crowdbake diff passes against the plain copy's (gltfpack's other changes are in both; meshopt's
# index codec may start a triangle at another corner, which diff counts); and three.js, decoding
# the -cc copy with meshoptimizer's own JavaScript decoder, poses it as crowdbake pose draws our
# bake of it (threejs_pose.mjs, float matrices: agreement at frame times). The -cc copy runs the
# same codecs as -c plus the filters, so the -c copy is not posed again (CI's time).
set -euo pipefail
. "$(dirname "$(realpath "$0")")/skip.sh"
bin=$1 root=$2 work=$3 assets=$4
need_node_tools "$root" gltfpack three
rm -rf "$work" && mkdir -p "$work" && cd "$work"
"$bin/crowdbake" samples --no-cloth --out s >/dev/null
models=(s/humanoid.glb)
if [ -d "$assets" ]; then
  models+=("$assets"/*/*.glb "$assets"/*/*.gltf)
else
  skip_part "no shared models at $assets (../shared beside the checkout): the sample only"
fi
status=0 count=0
for model in "${models[@]}"; do
  [ -f "$model" ] || continue
  name=$(basename "${model%.*}")
  "$tools/.bin/gltfpack" -i "$model" -o "$name.plain.glb" >/dev/null
  "$tools/.bin/gltfpack" -i "$model" -o "$name.c.glb" -c >/dev/null
  "$tools/.bin/gltfpack" -i "$model" -o "$name.cc.glb" -cc >/dev/null
  for v in plain c; do "$bin/crowdbake" anim "$name.$v.glb" -o "$name.$v.crowdpack" -q; done
  if "$bin/crowdbake" diff "$name.plain.crowdpack" "$name.c.crowdpack" >"$name.diff"; then
    echo "ok: $name: gltfpack -c bakes as the plain copy ($(tail -1 "$name.diff"))"
  else
    cat "$name.diff"; echo "FAIL: $name: gltfpack -c does not bake as the plain copy"; status=1
  fi
  "$bin/crowdbake" anim "$name.cc.glb" -o "$name.cc.float.crowdpack" --report "$name.cc.json" \
    -q --precision float --store texture
  node "$root/tests/scripts/threejs_pose.mjs" "$bin/crowdbake" "$tools/three" "$name.cc.glb" \
    "$name.cc.float.crowdpack" "$name.cc.json" . || status=1
  count=$((count + 1))
done
[ $status = 0 ] && echo "gltfpack: $count models' compressed copies decode as three.js decodes them"
[ $status != 0 ] || end_skipped_parts
exit $status
