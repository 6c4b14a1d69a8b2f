#!/usr/bin/env bash
# crowdbake diff's acceptance: a pack against itself and against a re-bake at another
# thread count exits 0; against a bake at another precision 1 or 2, naming the worst joint, clip
# and time; a truncated pack, a bad tolerances file and a FIFO for one exit 4 with one clear
# line; --report writes the verdict and the tolerances used.
set -euo pipefail
bin=$1 work=$2
rm -rf "$work" && mkdir -p "$work" && cd "$work"
"$bin/crowdbake" samples --no-cloth --out s >/dev/null
fail() { echo "FAIL: $*" >&2; exit 1; }
bake() { "$bin/crowdbake" anim s/humanoid.glb --fps 30 --store texture -q "$@"; }
bake --precision qts --threads 2 -o golden.crowdpack
bake --precision qts --threads 1 -o one_thread.crowdpack
bake --precision half --threads 2 -o half.crowdpack
diff_rc() { local rc=0; "$bin/crowdbake" diff "$@" > out.txt 2> err.txt || rc=$?; echo $rc; }

[ "$(diff_rc golden.crowdpack golden.crowdpack)" = 0 ] || fail "a pack against itself: $(cat out.txt)"
[ "$(diff_rc golden.crowdpack one_thread.crowdpack)" = 0 ] || fail "1 thread against 2: $(cat out.txt)"
rc=$(diff_rc golden.crowdpack half.crowdpack --report d.json)
case $rc in 1|2) ;; *) fail "qts against half exited $rc: $(cat out.txt err.txt)" ;; esac
grep -Eq "ANIM +animation displacement: .* mm, clip '[a-z]+', t [0-9.]+ s, vertex [0-9]+ \(joint '[a-z_]+'\)" out.txt ||
  fail "the worst clip, time, vertex and joint are not named: $(cat out.txt)"
python3 - <<'PY'
import json
d = json.load(open('d.json'))
assert d['verdict'] in ('warn', 'fail') and d['exit_code'] in (1, 2), d['verdict']
assert d['tolerances']['animation_mm'] == {'warn': 0.01, 'fail': 0.1}, d['tolerances']
anim = [i for i in d['items'] if i['chunk'] == 'ANIM' and i['what'] == 'animation displacement']
assert anim and anim[0]['value'] > 0.01 and "joint '" in anim[0]['worst'], anim
PY
echo '{"animation_mm": {"warn": 1000, "fail": 1000}}' > loose.json
[ "$(diff_rc golden.crowdpack half.crowdpack --tolerances loose.json)" = 0 ] ||
  fail "a loose tolerance still flags it: $(cat out.txt)"
cat out.txt

head -c 3000 golden.crowdpack > cut.crowdpack
[ "$(diff_rc golden.crowdpack cut.crowdpack)" = 4 ] || fail "a truncated pack did not exit 4"
[ "$(wc -l < err.txt)" = 1 ] && grep -q "^crowdbake: error: .*cut.crowdpack" err.txt ||
  fail "a truncated pack: $(cat err.txt)"
echo "ok: $(cat err.txt)"
echo '{"animation": 1}' > bad.json
[ "$(diff_rc golden.crowdpack golden.crowdpack --tolerances bad.json)" = 4 ] &&
  grep -q "unknown tolerance 'animation'" err.txt || fail "bad tolerances: $(cat err.txt)"
echo "ok: $(cat err.txt)"
mkfifo fifo.json # blocked the diff for good before
[ "$(diff_rc golden.crowdpack golden.crowdpack --tolerances fifo.json)" = 4 ] &&
  grep -q "fifo.json: not a regular file (a FIFO): nothing read" err.txt ||
  fail "a FIFO as the tolerances: $(cat err.txt)"
echo "ok: $(cat err.txt)"
"$bin/crowdbake" lod s/humanoid.glb --fps 30 --precision qts -q -o lod.crowdpack
[ "$(diff_rc golden.crowdpack lod.crowdpack)" = 3 ] || fail "a pack with a LOD chunk more: $(cat out.txt)"
grep -q "LODS.*only in the new pack" out.txt || fail "the extra chunk is not named: $(cat out.txt)"
echo "diff: all checks passed"
