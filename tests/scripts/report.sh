#!/usr/bin/env bash
# crowdbake report: a library build (two characters: LOD, outfits, a cloth loop,
# impostors) and a bake report into one page, which loads in Debian's chromium headless (its DOM
# holds every chart the page has, its screenshot is not blank, its console is silent); a JSON
# that is not a report and a folder without a build report are clear errors. Without chromium
# the page checks still run and the browser's are skipped, saying so (exit 77).
set -euo pipefail
. "$(dirname "$(realpath "$0")")/skip.sh"
bin=$1 work=$2
rm -rf "$work" && mkdir -p "$work" && cd "$work"
fail() { echo "FAIL: $*" >&2; exit 1; }
"$bin/crowdbake" samples --out s >/dev/null
cat > library.json <<'JSON'
{"characters": [
  {"name": "walker", "body": "s/humanoid.glb", "clips": ["walk", "run"], "lod": {"floor": 0.1},
   "anim": {"store": "both"}},
  {"name": "villager", "body": "s/humanoid.glb", "outfits": {"dress": "s/outfit_dress.glb"},
   "clips": ["walk"], "anim": {"fps": 30, "precision": "qts-half"},
   "visibility": {"rays": 12, "points": 1, "frame_step": 8, "loop_frames": 4},
   "impostor": {"clips": ["walk"], "outfits": ["dress"], "frames": 2, "views": "8x2",
                "texels": 32, "measure": true},
   "cloth": [{"outfit": "dress", "garment": "dress", "clip": "walk",
              "cache": "s/skirt_stiff.pc2", "fps": 30}]}]}
JSON
"$bin/crowdbake" build library.json -o lib -q
"$bin/crowdbake" impostor s/humanoid.glb --clip walk --frames 2 --views 8x2 --texels 32 \
  -o walk.crowdpack --report impostor.json -q
"$bin/crowdbake" report lib impostor.json -o report.html
svgs=$(grep -o "<svg" report.html | wc -l)
# walker: walk and run error against bytes (the texture searched: both stored), LOD; villager: LOD, cloth, impostors; the bake: impostors
[ "$svgs" -ge 7 ] || fail "$svgs charts in the page, expected at least 7"
for want in "<h2>walker</h2>" "<h2>villager</h2>" "Animation &#39;run&#39;: error against bytes" \
  "LOD: error against triangles" "Impostors: accuracy against memory" \
  "pass 1, the best seam per loop length" "crowdbake impostor of s/humanoid.glb"; do
  grep -qF "$want" report.html || fail "the page lacks '$want'"
done
echo "ok: report.html, $(stat -c %s report.html) bytes, $svgs charts"

expect_error() { # expect_error PATTERN command...
  local pattern=$1; shift
  local rc=0; "$@" 2>err.txt >/dev/null || rc=$?
  [ $rc = 1 ] && grep -Eq "$pattern" err.txt || fail "$*: exit $rc, $(cat err.txt)"
  echo "ok: $(cat err.txt)"
}
echo '{"name": "x"}' > not_a_report.json
expect_error "not_a_report.json: neither a build report" "$bin/crowdbake" report not_a_report.json -o x.html
mkdir -p empty
expect_error "build.report.json: cannot open \(not a build's output folder\?\)" \
  "$bin/crowdbake" report empty -o x.html
# What is not a report file: read whole before, /dev/zero grew until memory ran out.
expect_error "/dev/zero: not a regular file \(a device\): nothing read" \
  "$bin/crowdbake" report /dev/zero -o x.html
python3 -c "print('[' * 100000 + ']' * 100000)" > deep.json
expect_error "deep.json:1:65: JSON nests deeper than 64 levels" "$bin/crowdbake" report deep.json -o x.html
[ ! -e x.html ] || fail "a failed report wrote its page"

browser=$(command -v chromium || command -v chromium-browser || true)
[ -n "$browser" ] ||
  skip "chromium is not installed (apt-get install chromium): the page was not loaded in a browser"
chrome() { timeout 120 "$browser" --headless --no-sandbox --disable-gpu --hide-scrollbars \
  --user-data-dir="$work/profile" --enable-logging=stderr --v=0 "$@" "file://$work/report.html"; }
chrome --dump-dom > dom.html 2> chromium_dom.log || fail "chromium could not load the page: $(tail -3 chromium_dom.log)"
dom_svgs=$(grep -o "<svg" dom.html | wc -l)
[ "$dom_svgs" = "$svgs" ] || fail "chromium's DOM holds $dom_svgs charts, the page $svgs"
chrome --window-size=1280,4000 --screenshot="$work/report.png" > /dev/null 2> chromium_shot.log ||
  fail "chromium could not take a screenshot: $(tail -3 chromium_shot.log)"
# A blank 1280x4000 page compresses to a few kB; charts and tables do not.
[ "$(stat -c %s report.png)" -gt 50000 ] || fail "the screenshot looks blank ($(stat -c %s report.png) bytes)"
! grep -h "CONSOLE\|Uncaught" chromium_dom.log chromium_shot.log || fail "the page logged errors"
echo "report: all checks passed ($dom_svgs charts in chromium's DOM; screenshot $work/report.png)"
