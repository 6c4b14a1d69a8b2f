#!/usr/bin/env bash
# The one way to refresh the goldens, after a deliberate change (say why in the commit): bakes
# every golden pack and renders the golden screenshot with the build in BIN_DIR, prints what
# changed against each golden, then writes them over tests/golden. Review `git diff --stat
# tests/golden` before committing.
#   tests/golden/update.sh [BIN_DIR]     (default: build/bin)
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
bin=$(realpath "${1:-$root/build/bin}")
[ -x "$bin/crowdbake" ] && [ -x "$bin/crowd_render_tests" ] ||
  { echo "update.sh: no crowdbake or crowd_render_tests in $bin (build first)" >&2; exit 1; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$root/tests/scripts/golden.sh" "$bin" "$root/tests/golden" "$work/packs" --update
echo "== small_scene.png: the render against its golden, then written over it"
mkdir -p "$work/render" && cd "$work/render"
# The test copies its render to CROWD_UPDATE_GOLDEN and fails by design (its output is the
# comparison): the golden is written only where the render came out.
fresh=$work/render/small_scene.png
CROWD_UPDATE_GOLDEN=$fresh "$root/tests/scripts/xvfb.sh" "$bin/crowd_render_tests" \
  --gtest_filter=Player.SmallSceneMatchesItsGoldenScreenshot 2>&1 |
  grep -E "against the golden|copied to|Failure|error" || true
[ -s "$fresh" ] || { echo "update.sh: the render did not run; small_scene.png is unchanged" >&2; exit 1; }
cp "$fresh" "$root/tests/golden/small_scene.png"
echo "goldens refreshed; review: git -C $root diff --stat tests/golden"
