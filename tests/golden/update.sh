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
# The test fails by design once it has written the golden: its output is the comparison.
CROWD_UPDATE_GOLDEN=1 "$root/tests/scripts/xvfb.sh" "$bin/crowd_render_tests" \
  --gtest_filter=Player.SmallSceneMatchesItsGoldenScreenshot 2>&1 |
  grep -E "against the golden|refreshed|Failure|error" || true
echo "goldens refreshed; review: git -C $root diff --stat tests/golden"
