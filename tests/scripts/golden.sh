#!/usr/bin/env bash
# Golden packs, one per bake (anim, lod, outfits, impostor, cloth, terrain and a character pack
# built from a manifest holding all of them), in tests/golden. Each fresh bake is compared with its golden by
# `crowdbake diff` under its default tolerances (exit 0 needed), and must also be byte-identical
# where this crowdbake was built with the toolchain the goldens were (tests/golden/toolchain.txt):
# on another compiler or C library, floats may round differently and the tolerance check decides.
#
# Refresh only after a deliberate change, with tests/golden/update.sh (say why in the commit);
# it passes --update here and prints what changed. No environment variable refreshes: ctest's
# environment cannot rewrite the goldens.
set -euo pipefail
bin=$1 golden=$2 work=$3 mode=${4:-check}
if [ -n "${CROWD_UPDATE_GOLDEN:-}" ] && [ "$mode" != --update ]; then
  echo "golden: CROWD_UPDATE_GOLDEN is set: the check refuses to run under it (refresh with" \
    "tests/golden/update.sh)" >&2
  exit 1
fi
rm -rf "$work" && mkdir -p "$work" && cd "$work"
cb() { "$bin/crowdbake" "$@"; }
cb samples --out s >/dev/null
# The settings are small where the defaults would make a large file (the impostor, the outfit
# frames, the cloth loop of the stiff skirt, one cycle long). Both stores are covered: the
# manifest's character and humanoid.anim keep joint tracks, the rest force a texture precision.
cat > villager.json <<'JSON'
{"name": "villager", "body": "s/humanoid.glb", "outfits": {"dress": "s/outfit_dress.glb"},
 "clips": ["walk"], "anim": {"fps": 30, "store": "tracks"}, "lod": {"floor": 0.1},
 "visibility": {"rays": 12, "points": 1, "frame_step": 8, "loop_frames": 4},
 "impostor": {"clips": ["walk"], "outfits": ["dress"], "frames": 2, "views": "8x2", "texels": 32},
 "cloth": [{"outfit": "dress", "garment": "dress", "clip": "walk", "cache": "s/skirt_stiff.pc2",
            "fps": 30}]}
JSON
bake() { # bake NAME crowdbake-arguments...: writes NAME.crowdpack
  local name=$1; shift
  cb "$@" -o "$name.crowdpack" -q
}
bake humanoid.anim anim s/humanoid.glb
bake outfit_dress.anim anim s/outfit_dress.glb --fps 30 --precision qts-half
bake humanoid.lod lod s/humanoid.glb --clip walk --fps 30 --precision qts-half
bake humanoid.outfits outfits s/humanoid.glb --outfit s/outfit_dress.glb \
  --outfit s/outfit_shirt_trousers.glb --fps 10 --precision qts-half --frame-step 4 --rays 12 --points 1
bake humanoid_walk.impostor impostor s/humanoid.glb --clip walk --frames 2 --views 8x2 --texels 32
bake skirt_stiff.cloth cloth s/skirt_stiff.pc2 --body s/humanoid.glb --outfit s/outfit_dress.glb \
  --garment dress --clip walk --fps 30
bake villager.character build villager.json
bake village.terrain terrain s/village.glb --cell 1

toolchain=$(cb --version | sed -n 's/^built with //p')
if [ "$mode" = --update ]; then
  for pack in *.crowdpack; do
    if [ -f "$golden/$pack" ]; then
      echo "== $pack: what changed"
      cb diff "$golden/$pack" "$pack" || true
    else
      echo "== $pack: new golden"
    fi
    cp "$pack" "$golden/$pack"
  done
  echo "$toolchain" > "$golden/toolchain.txt"
  echo "goldens refreshed with $toolchain"
  exit 0
fi

exact=0
[ "$toolchain" = "$(cat "$golden/toolchain.txt")" ] && exact=1
status=0
for goldpack in "$golden"/*.crowdpack; do
  pack=$(basename "$goldpack")
  [ -f "$pack" ] || { echo "golden $pack: no bake writes it any more" >&2; status=1; continue; }
done
for pack in *.crowdpack; do
  [ -f "$golden/$pack" ] || { echo "$pack: no golden (refresh to add it)" >&2; status=1; continue; }
  rc=0
  cb diff "$golden/$pack" "$pack" > "$pack.diff.txt" || rc=$?
  if [ $rc != 0 ]; then
    echo "golden mismatch: $pack (crowdbake diff exit $rc)" >&2
    cat "$pack.diff.txt" >&2
    status=1
  elif ! cmp -s "$golden/$pack" "$pack"; then
    if [ $exact = 1 ]; then
      echo "golden mismatch: $pack is within tolerance but not byte-identical on the goldens'" \
        "toolchain ($toolchain)" >&2
      cat "$pack.diff.txt" >&2
      status=1
    else
      echo "$pack: within tolerance, not byte-identical (built with $toolchain; goldens with" \
        "$(cat "$golden/toolchain.txt"))"
    fi
  fi
done
[ $status = 0 ] && echo "goldens match ($([ $exact = 1 ] && echo byte-identical || echo within tolerance))"
exit $status
