#!/usr/bin/env bash
# crowdplay with a world (issue 16): samples/scenes/village.json's agents walk the sample
# village's terrain and draw (headless, Mesa under Xvfb); a behaviour image of another size than
# the terrain's grid and a missing terrain pack are one-line errors.
set -euo pipefail
bin=$1 work=$2 src=$3
rm -rf "$work" && mkdir -p "$work/samples/scenes" "$work/out" && cd "$work"
fail() { echo "FAIL: $*" >&2; exit 1; }
cb() { "$bin/crowdbake" "$@"; }
cb samples --no-cloth --out out/samples >/dev/null
cb lod out/samples/humanoid.glb -o out/humanoid.crowdpack --poses 2 -q
cb impostor out/samples/humanoid.glb -o out/humanoid_walk.impostor.crowdpack --clip walk \
  --frames 4 --views 8x2 --texels 32 --mirror -q
cb terrain out/samples/village.glb -o out/village.crowdpack -q
cp "$src/samples/scenes/village.json" samples/scenes/
play() { # play SCENE crowdplay-options...: exit code, stderr in err.txt
  local rc=0
  xvfb-run -a -s "-screen 0 640x480x24" "$bin/crowdplay" "$@" --headless --size 320x180 \
    > out.txt 2> err.txt || rc=$?
  echo $rc
}
rc=$(play samples/scenes/village.json --instances 400 --frames 2 --time 25 --screenshot v.png \
  --stats v.json)
[ "$rc" = 0 ] || fail "the village did not draw (exit $rc): $(cat err.txt)"
[ -s v.png ] || fail "no screenshot"
python3 - <<'PY'
import json
s = json.load(open('v.json'))['summary']
assert s['instances'] == 400 and s['visible'] > 0, s
print('ok: village, 400 agents:', {k: s[k] for k in ('instances', 'visible', 'impostors')})
PY
cb export out/humanoid.crowdpack --images tex >/dev/null
sed 's|../../out/samples/village_behaviour.png|../../tex/diffuse.png|' \
  samples/scenes/village.json > samples/scenes/wrong_size.json
rc=$(play samples/scenes/wrong_size.json --instances 10 --frames 1)
[ "$rc" = 1 ] && grep -q "diffuse.png: the behaviour image is 256x256 pixels; the terrain's grid is 320x320 cells" err.txt ||
  fail "a behaviour image of another size (exit $rc): $(cat err.txt)"
echo "ok: $(cat err.txt)"
sed 's|../../out/village.crowdpack|../../out/none.crowdpack|' samples/scenes/village.json \
  > samples/scenes/no_terrain.json
rc=$(play samples/scenes/no_terrain.json --instances 10 --frames 1)
[ "$rc" = 1 ] && grep -q "does not exist (bake it: crowdbake terrain)" err.txt ||
  fail "a missing terrain pack (exit $rc): $(cat err.txt)"
echo "ok: $(cat err.txt)"
echo "world: all checks passed"
