#!/usr/bin/env bash
# The outfit hole check fails where it should: visibility forced coarse (3 rays, one
# point per face, every 30th frame, no ring) hides faces that show, and both `outfits --check K`
# and a library build with "visibility": {"check": K} exit 1 with one error naming the body
# parts, the frame and the view. With FULL=1 (release) the sample outfits at the tests' settings
# pass the same check: no false alarm.
set -euo pipefail
bin=$1 work=$2
rm -rf "$work" && mkdir -p "$work" && cd "$work"
"$bin/crowdbake" samples --no-cloth --out . >/dev/null
fail() { echo "FAIL: $*" >&2; exit 1; }
named='hole check failed: outfit .shirt_trousers. shows body faces \((arms|legs|torso) [0-9]+.*\) through a hole in [0-9]+ pixels at clip .[a-z]+. frame [0-9]+ \([0-9.]+ s\), (orthographic|perspective) view azimuth [0-9]+ deg'

rc=0
"$bin/crowdbake" outfits humanoid.glb --outfit outfit_shirt_trousers.glb -o coarse.crowdpack \
  --rays 3 --points 1 --ring 0 --frame-step 30 --check 30 --quiet 2> err.txt || rc=$?
[ "$rc" = 1 ] || fail "outfits --check on a coarse bake exited $rc: $(cat err.txt)"
[ "$(wc -l < err.txt)" = 1 ] && grep -Eq "^crowdbake: error: $named" err.txt ||
  fail "the error does not name the parts, the frame and the view: $(cat err.txt)"
[ ! -e coarse.crowdpack ] || fail "a bake that failed its hole check wrote its pack"

cat > library.json <<'JSON'
{"characters": [{"name": "clothed", "body": "humanoid.glb",
  "outfits": {"shirt_trousers": "outfit_shirt_trousers.glb"}, "lod": {"poses": 2},
  "visibility": {"rays": 3, "points": 1, "ring": 0, "frame_step": 30, "check": 30}}]}
JSON
rc=0
"$bin/crowdbake" build library.json -o library --quiet 2> build_err.txt || rc=$?
[ "$rc" = 1 ] || fail "a build with a failing hole check exited $rc: $(cat build_err.txt)"
grep -Eq "clothed: .*$named" build_err.txt || fail "the build's error: $(cat build_err.txt)"
[ ! -e library/clothed.crowdpack ] || fail "the build wrote the pack whose check failed"
python3 - <<'PY'
import json
r = json.load(open('library/build.report.json'))
text = json.dumps(r)
assert 'hole check failed' in text and 'shows body faces' in text, 'the report does not say why'
PY

if [ "${FULL:-0}" = 1 ]; then # every 8th frame, joint regions, a ring of 2: the unit tests' settings
  "$bin/crowdbake" outfits humanoid.glb --outfit outfit_dress.glb --outfit outfit_jumper_skirt.glb \
    --outfit outfit_shirt_trousers.glb -o clothed.crowdpack --frame-step 8 --regions joint \
    --ring 2 --check 8 --quiet || fail "the sample outfits failed the hole check (a false alarm)"
fi
echo "hole check: coarse bakes fail naming part, frame and view; build fails alike"
