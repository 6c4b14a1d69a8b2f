#!/usr/bin/env bash
# crowdbake build --scene: only what a scene draws is built (its characters, clips and outfits;
# impostors only for pairs shown past the switch distance, texels from that distance), the report
# says what was left out and what it saved against a full build in the same cache, the player
# draws the result, and a scene that does not fit the library is one clear error.
set -euo pipefail
. "$(dirname "$(realpath "$0")")/skip.sh"
bin=$1 work=$2
xvfb=$(dirname "$(realpath "$0")")/xvfb.sh # the player under a fresh X display
rm -rf "$work" && mkdir -p "$work" && cd "$work"
"$bin/crowdbake" samples --no-cloth --out s >/dev/null
fail() { echo "FAIL: $*" >&2; exit 1; }
json() { python3 -c "import json, sys; r = json.load(open('$1')); print($2)"; }

cat > library.json <<'JSON'
{"characters": [
  {"name": "walker", "body": "s/humanoid.glb", "lod": {"poses": 2},
   "impostor": {"clips": ["walk", "run"], "frames": 2, "views": "4x2", "texels": 16}},
  {"name": "runner", "body": "s/humanoid.glb", "clips": ["run"], "lod": {"poses": 2}}
]}
JSON
# 40 walkers walking or idling from 6 m to 128 m away; nobody runs.
cat > scene.json <<'JSON'
{"packs": [{"name": "walker", "path": "out/walker.crowdpack"}],
 "instances": {"count": 40, "pack": "walker", "seed": 3, "clip": {"walk": 0.5, "idle": 0.5},
   "placement": {"type": "random", "min": [-3, 0, -120], "max": [3, 0, 2]}},
 "camera": {"position": [0, 1.6, 8], "target": [0, 1, 0], "fov": 50}}
JSON
"$bin/crowdbake" build library.json -o full -q
"$bin/crowdbake" build library.json -o out --cache full/.cache --scene scene.json -q
r=out/build.report.json
[ ! -e out/runner.crowdpack ] || fail "a character the scene does not draw was built"
[ "$(json $r "r['scene']['characters'][1]['left_out']")" = "the scene draws no instance of it" ] ||
  fail "the report does not say why runner was left out"
[ "$(json $r "r['scene']['characters'][0]['clips_left_out']['names']")" = "['run']" ] ||
  fail "the unplayed clip was not left out"
"$bin/crowdbake" inspect out/walker.crowdpack --json > walker.json
[ "$(json walker.json "[c['name'] for c in [ch for ch in r['chunks'] if ch['type'] == 'CLIP'][0]['content']['clips']]")" = "['walk', 'idle']" ] ||
  fail "the pack does not hold exactly the scene's clips"
# At 16 texels the walkers switch at ~132 m: none gets that far, so no impostor is baked.
[ "$(json walker.json "sum(c['type'] == 'IMPO' for c in r['chunks'])")" = 0 ] || fail "impostors baked that no pixel shows"
json $r "r['scene']['characters'][0]['impostors_left_out'][0]['why']" | grep -q "switch distance" ||
  fail "the report does not say why the walk impostor was left out"
saved=$(json $r "r['scene']['saved']['pack_bytes']")
[ "$saved" -gt 0 ] && [ "$(json $r "r['scene']['saved']['bake_s'] > 0")" = True ] ||
  fail "no saving measured against the full build: $(json $r "r['scene']")"
echo "ok: scene build of 1 character of 2, 2 clips of 3, no impostor; saved $saved pack bytes"

# Switching at 20 m: the walk impostor is needed, run's is not; a texel covers at most a pixel
# at 20 m on a 1080-pixel screen (the fewest texels, a multiple of 4, that do): the player
# switches where a texel covers a pixel, at or just before 20 m.
"$bin/crowdbake" build library.json -o out20 --cache full/.cache --scene scene.json \
  --switch-distance 20 --screen 1080 -q
"$bin/crowdbake" verify out20/walker.crowdpack
"$bin/crowdbake" inspect out20/walker.crowdpack --json > walker20.json
python3 - walker20.json <<'PY'
import json, math, sys
chunks = json.load(open(sys.argv[1]))['chunks']
imp = [c['content'] for c in chunks if c['type'] == 'IMPO']
assert [(m['clip'], m['outfit']) for m in imp] == [('walk', '')], imp
m = imp[0]
switch = lambda texels: 2 * m['sphere_radius'] / texels * 1080 / (2 * math.tan(math.radians(25)))
assert switch(m['texels']) <= 20 < switch(m['texels'] - 4), (m['texels'], switch(m['texels']))
print(f"ok: walk impostor at {m['texels']} texels switches at {switch(m['texels']):.1f} m (asked 20 m)")
PY
if command -v Xvfb >/dev/null; then
  sed 's#out/walker#out20/walker#' scene.json > scene20.json
  "$xvfb" "$bin/crowdplay" scene20.json --headless --frames 2 \
    --size 1920x1080 --stats stats.json >/dev/null
  impostors=$(json stats.json "int(r['summary']['impostors'])")
  [ "$impostors" -gt 0 ] || fail "the player drew no impostor of the scene build"
  echo "ok: the player draws the scene build ($impostors of 40 as impostors)"
else
  skip_part "Xvfb is not installed: the player check did not run"
fi

# A scene that does not fit the library: one clear error each.
sed 's#out/walker#out/nobody#' scene.json > nobody.json
rc=0; "$bin/crowdbake" build library.json -o bad --scene nobody.json -q 2>err.txt || rc=$?
[ $rc = 1 ] && grep -q "draws none of the library's characters" err.txt || fail "nobody: $rc $(cat err.txt)"
sed 's#"idle": 0.5#"dance": 0.5#' scene.json > dance.json
rc=0; "$bin/crowdbake" build library.json -o bad --scene dance.json -q 2>err.txt || rc=$?
[ $rc = 1 ] && grep -q "character 'walker' has no clip 'dance' (clips: walk, run, idle)" err.txt ||
  fail "dance: $rc $(cat err.txt)"
rc=0; "$bin/crowdbake" build library.json -o bad --screen 720 -q 2>err.txt || rc=$?
[ $rc = 2 ] || fail "--screen without --scene exited $rc"
echo "ok: scenes that do not fit the library, one clear error each"
end_skipped_parts
