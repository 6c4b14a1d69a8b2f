#!/usr/bin/env bash
# crowdbake export --gltf, read by the tools a user has: every sample (the humanoid as its LOD
# bake, as an animation texture and cut at 1,200 vertices; the clothed pack's two outfits) and
# every model of ../shared/assets/gltf (at the bake's choice of store; as an animation texture
# too for CesiumMan, Fox and RecursiveSkeletons, the rigs with the most joints, which bounds
# CI's time) exported, then checked by the Khronos validator (0 errors), three.js (threejs_export.mjs:
# its pose at 6 random times a clip within the pack's own any-time error of crowdbake pose) and
# Blender's importer (the same joints and clips as crowdbake inspect). Failure modes: a pack
# without a skeleton, an unknown outfit, a LOD cut the pack lacks, no output asked for.
set -euo pipefail
. "$(dirname "$(realpath "$0")")/skip.sh"
bin=$1 root=$2 work=$3 assets=$4
need_node_tools "$root" gltf-validator three
rm -rf "$work" && mkdir -p "$work" && cd "$work"
fail() { echo "FAIL: $*" >&2; exit 1; }
cb() { "$bin/crowdbake" "$@"; }
cb samples --no-cloth --out s >/dev/null
exports=() # "PACK GLB REPORT [POSE ARGS]"
export_one() { # export_one PACK REPORT NAME [EXPORT/POSE ARGS]
  local pack=$1 report=$2 name=$3; shift 3
  cb export "$pack" --gltf "$name.glb" "$@" >/dev/null 2>"$name.warnings"
  exports+=("$pack $name.glb $report $*")
}
cb lod s/humanoid.glb -o humanoid.crowdpack --report humanoid.json -q
export_one humanoid.crowdpack humanoid.json humanoid
export_one humanoid.crowdpack humanoid.json humanoid_lod1200 --lod 1200
cb anim s/humanoid.glb -o humanoid_texture.crowdpack --report humanoid_texture.json -q --store texture
export_one humanoid_texture.crowdpack humanoid_texture.json humanoid_texture
cb outfits s/humanoid.glb --outfit s/outfit_dress.glb --outfit s/outfit_shirt_trousers.glb \
  -o clothed.crowdpack --report clothed.json -q --frame-step 8
export_one clothed.crowdpack clothed.json clothed_dress --outfit dress
export_one clothed.crowdpack clothed.json clothed_shirt_trousers --outfit shirt_trousers
if [ -d "$assets" ]; then
  for model in "$assets"/*/*.glb "$assets"/*/*.gltf; do
    [ -f "$model" ] || continue
    name=$(basename "${model%.*}")
    cb lod "$model" -o "$name.crowdpack" --report "$name.json" -q
    export_one "$name.crowdpack" "$name.json" "$name"
    case $name in CesiumMan | Fox | RecursiveSkeletons) ;; *) continue ;; esac
    cb anim "$model" -o "${name}_texture.crowdpack" --report "${name}_texture.json" -q --store texture
    export_one "${name}_texture.crowdpack" "${name}_texture.json" "${name}_texture"
  done
else
  skip_part "no shared models at $assets (../shared beside the checkout): the samples only"
fi

status=0
node "$root/tests/scripts/validate.js" "$tools/gltf-validator" *.glb || status=1
for e in "${exports[@]}"; do
  read -r pack glb report args <<<"$e"
  # shellcheck disable=SC2086 # the pose arguments, word by word
  node "$root/tests/scripts/threejs_export.mjs" "$bin/crowdbake" "$tools/three" "$pack" "$glb" \
    "$report" . $args || status=1
done
if command -v blender >/dev/null; then
  blender -b --python-exit-code 1 --python "$root/tests/scripts/blender_import.py" -- *.glb \
    >blender.log 2>&1 ||
    { tail -20 blender.log; fail "Blender's import failed"; }
  for e in "${exports[@]}"; do
    read -r pack glb _ <<<"$e"
    CROWDBAKE=$bin/crowdbake python3 - "$pack" "$glb" blender.log <<'PY' || status=1
import json, subprocess, sys, os
pack, glb, log = sys.argv[1:]
info = json.loads(subprocess.check_output([os.environ['CROWDBAKE'], 'inspect', pack, '--json']))
content = {c['type']: c['content'] for c in info['chunks']}
found = [json.loads(l[7:]) for l in open(log) if l.startswith('RESULT ') and os.path.basename(json.loads(l[7:])['file']) == glb]
if not found:
    sys.exit(f'FAIL: {glb}: Blender printed nothing for it')
b = found[0]
joints = len(content['SKEL']['joints'])
clips = sorted(c['name'] for c in content['CLIP']['clips'])
ok = b['joints'] == joints and b['clips'] == clips
print(f"{'ok' if ok else 'FAIL'}: {glb}: Blender imports {b['joints']} joints and clips {b['clips']}; "
      f"the pack has {joints} joints and clips {clips}")
sys.exit(0 if ok else 1)
PY
  done
else
  skip_part "blender is not installed: the Blender import check did not run (./run test installs it)"
fi

expect_error() { # expect_error PATTERN command...
  local pattern=$1; shift
  if "$@" >/dev/null 2>err.txt; then fail "$* succeeded"; fi
  grep -q "$pattern" err.txt || fail "$*: expected '$pattern' in: $(cat err.txt)"
  echo "ok: $(cat err.txt)"
}
cb terrain s/village.glb -o village.crowdpack -q
expect_error "needs a character pack" cb export village.crowdpack --gltf v.glb
expect_error "no outfit named 'cape'\|outfit 'cape'" cb export clothed.crowdpack --gltf c.glb --outfit cape
expect_error "the pack has no LOD" cb export clothed.crowdpack --gltf c.glb --lod 100
expect_error "nothing to export" cb export humanoid.crowdpack
[ $status = 0 ] && echo "export --gltf: ${#exports[@]} files valid, posed by three.js as by crowdbake pose"
[ $status != 0 ] || end_skipped_parts
exit $status
