#!/usr/bin/env bash
# crowdplay's window, driven by real key presses (xdotool under Xvfb): previewing a character pack,
# C cycles the clip, O the outfit, L the level of detail and I the drawing, and the title names
# each choice. Skips (exit 77), saying why, without xdotool.
set -euo pipefail
. "$(dirname "$(realpath "$0")")/skip.sh"
bin=$1 work=$2
command -v xdotool >/dev/null || skip "xdotool is not installed (./run test installs it)"
rm -rf "$work" && mkdir -p "$work" && cd "$work"
"$bin/crowdbake" samples --no-cloth --out s >/dev/null
cat > pair.json <<'JSON'
{"name": "pair", "body": "s/humanoid.glb", "clips": ["walk", "run"], "lod": {"poses": 2},
 "outfits": {"dress": "s/outfit_dress.glb"}, "visibility": {"frame_step": 8, "ring": 2},
 "impostor": {"clips": ["walk"], "outfits": ["dress"], "frames": 2, "views": "4x2", "texels": 32}}
JSON
"$bin/crowdbake" build pair.json -o pair.crowdpack --quiet
"$bin/crowdplay" pair.crowdpack --size 320x240 > play.log 2>&1 &
play=$!
trap 'kill $play 2>/dev/null || true' EXIT
fail() { echo "FAIL: $*" >&2; cat play.log >&2; exit 1; }
win=
for _ in $(seq 300); do
  win=$(xdotool search --name '^crowdplay' 2>/dev/null | head -1) && [ -n "$win" ] && break
  kill -0 $play 2>/dev/null || fail "crowdplay exited before opening its window"
  sleep 0.2
done
[ -n "$win" ] || fail "no crowdplay window"
# The title holds the choice, then '|' and the frame's figures; it is refreshed each frame after a
# key, so wait until it shows what a key should have chosen.
expect_title() { # expect_title PATTERN
  for _ in $(seq 200); do
    title=$(xdotool getwindowname "$win")
    [[ $title == *"|"* && $title =~ $1 ]] && { echo "ok: $title"; return 0; }
    sleep 0.1
  done
  fail "title '$title' does not match '$1'"
}
expect_title 'pair  clip all  outfit all  LOD auto  hybrid  \|  .* 4 of 4 visible'
xdotool windowfocus --sync "$win"
xdotool key c && expect_title 'clip walk  outfit all  LOD auto  hybrid  \|  .* 2 of 2 visible'
xdotool key c && expect_title 'clip run  outfit all'
xdotool key c && expect_title 'clip all  outfit all'
xdotool key o && expect_title 'clip all  outfit dress  LOD auto'
xdotool key c && expect_title 'clip walk  outfit dress  LOD auto  hybrid  \|  .* 2 of 2 visible'
xdotool key l && expect_title 'LOD 100%  hybrid'
xdotool key l && expect_title 'LOD 50%  hybrid'
xdotool key i && expect_title 'LOD 50%  geometry only  \|  .*\(0 impostors\)'
xdotool key i && expect_title 'LOD 50%  impostors only  \|  .* visible \(2 impostors\)'
# A tap shorter than a frame (xdotool's is ~12 ms) must still close it: crowdplay once polled the
# key's state each frame and, on a loaded machine, missed the tap and never exited.
xdotool key Escape
for _ in $(seq 300); do kill -0 $play 2>/dev/null || break; sleep 0.1; done
kill -0 $play 2>/dev/null && fail "crowdplay still runs 30 s after Esc"
wait $play || fail "crowdplay exited $? after Esc"
echo "ok: Esc closed the window"
