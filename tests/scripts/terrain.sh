#!/usr/bin/env bash
# crowdbake terrain from the command line: the sample village bakes, verifies, exports
# its three maps and is byte-identical at 1 and 2 threads; bad options are usage errors (exit 2)
# and bad environments one-line errors (exit 1) that leave no pack behind.
set -euo pipefail
bin=$1 work=$2
rm -rf "$work" && mkdir -p "$work" && cd "$work"
cb() { "$bin/crowdbake" "$@"; }
fail() { echo "FAIL: $*" >&2; exit 1; }
cb samples --no-cloth --out s >/dev/null
cb terrain s/village.glb -o one.crowdpack --threads 1 --report one.json -q
cb terrain s/village.glb -o two.crowdpack --threads 2 -q
cmp one.crowdpack two.crowdpack || fail "1 and 2 threads bake different bytes"
cb verify one.crowdpack | grep -q "terrain of 320x320 cells of 0.25" || fail "verify: $(cb verify one.crowdpack)"
cb inspect one.crowdpack --json > inspect.json
python3 - <<'PY'
import json
r = json.load(open('one.json'))
t = r['terrain']
assert t['cells'] == [320, 320] and t['empty_cells'] == 0, t
# Measured: 94,056 walkable (4,959 in shadow), 8,344 blocked, all unreachable: each within 2x.
assert 80000 < t['walkable_cells'] <= 102400 - t['blocked_cells'], t
assert 2480 <= t['walkable_cells_in_shadow'] <= 9918, t
assert 4172 <= t['blocked_cells'] <= 16688 and t['unreachable_cells'] == t['blocked_cells'], t
assert [w['code'] for w in r['warnings']] == ['terrain_unreachable'], r['warnings']
assert r['input_triangles'] > 0 and r['time_s'] > 0, r
print('ok: village', t)
PY
cb export one.crowdpack --images maps >/dev/null
for f in heights.exr walkable.png shadow_heights.exr; do
  [ -s "maps/$f" ] || fail "export wrote no maps/$f"
done

# crowdbake diff compares terrains map by map: another light moves the shadow heights only.
cb diff one.crowdpack two.crowdpack > /dev/null || fail "diff of two equal bakes"
cb terrain s/village.glb -o low_sun.crowdpack --light 1,0.5,0 -q
rc=0; cb diff one.crowdpack low_sun.crowdpack > diff.txt || rc=$?
[ $rc = 2 ] && grep -q "fail .*TERR .*shadow heights: .* mm, cell (" diff.txt &&
  grep -q "pass .*TERR .*heights: 0 mm" diff.txt || fail "diff of another light (exit $rc): $(cat diff.txt)"
echo "ok: diff: $(grep 'shadow heights' diff.txt)"

expect() { # expect CODE PATTERN crowdbake-arguments...
  local code=$1 pattern=$2 rc=0; shift 2
  cb "$@" > out.txt 2> err.txt || rc=$?
  [ "$rc" = "$code" ] || fail "crowdbake $* exited $rc, not $code: $(cat err.txt)"
  [ "$(wc -l < err.txt)" = 1 ] && grep -q -- "$pattern" err.txt ||
    fail "crowdbake $*: $(cat err.txt)"
  echo "ok: $(cat err.txt)"
}
expect 2 "--light expects X,Y,Z" terrain s/village.glb -o bad.crowdpack --light 1,2
expect 2 "above the horizon" terrain s/village.glb -o bad.crowdpack --light 0,-1,0
expect 2 "'cell'" terrain s/village.glb -o bad.crowdpack --cell 0
expect 1 "raise --cell" terrain s/village.glb -o bad.crowdpack --cell 0.001
[ ! -e bad.crowdpack ] || fail "a failed bake left a pack"
head -c 2000 one.crowdpack > cut.crowdpack
expect 1 "cut.crowdpack" verify cut.crowdpack
echo "terrain: all checks passed"
