#!/usr/bin/env bash
# A library build's jobs in child processes: a runaway job (held) past --job-max-seconds, one past
# its manifest's memory limit (a clip stretched 100x, baked at 30 fps, texture and tracks), one
# killed with SIGKILL
# (run again), an interrupted build that the next build finishes, two builds with different
# limits sharing a cache, and a limit that is not a number. Each case acts on events (a held job,
# its pid file, a process's end; CROWD_JOB_HOLD, docs/farm.md), never on how long a bake takes.
set -euo pipefail
here=$(dirname "$(realpath "$0")")
bin=$1 work=$2
rm -rf "$work" && mkdir -p "$work" && cd "$work"
"$bin/crowdbake" samples --no-cloth --out s >/dev/null
python3 "$here/stretch_clips.py" s/humanoid.glb heavy.glb 100 # only the memory case bakes it
fail() { echo "FAIL: $*" >&2; exit 1; }
library() { # library SLOW_EXTRA [QUICK_EXTRA [SLOW_BODY]]: the slow character between two quick ones
  cat <<JSON
{"characters": [
  {"name": "walker", "body": "s/humanoid.glb", "clips": ["walk"]${2:-}},
  {"name": "slow", "body": "${3:-s/humanoid.glb}", "clips": ["walk"], "anim": {"fps": 30, "store": "both"}$1},
  {"name": "runner", "body": "s/humanoid.glb", "clips": ["run"], "lod": {"floor": 0.1}${2:-}}
]}
JSON
}
status() { # status REPORT NAME: the character's status and error
  python3 -c "
import json, sys
r = json.load(open(sys.argv[1]))
c = [c for c in r['characters'] if c['name'] == sys.argv[2]][0]
print(c['status'], c.get('error', ''))" "$@"
}
library '' > lib.json
# The slow character's first job (entry 1, job 0) waits once, from its start until released.
export CROWD_JOB_HOLD=$PWD/hold
hold() { rm -rf hold && mkdir hold && : > hold/1.0.hold; }
release() { rm hold/1.0.held; }
held() { # held BUILD_PID: until the held job runs (a bounded poll of an event); prints its pid
  for _ in $(seq 2400); do
    [ -e hold/1.0.held ] && { cat hold/1.0.pid; return 0; }
    kill -0 "$1" 2>/dev/null || fail "the build ended before its slow job started"
    sleep 0.05
  done
  fail "the slow job never started"
}
ended() { # ended PID: true once the process is gone (or a zombie no one reaps)
  [ ! -e /proc/$1 ] || [ "$(awk '{print $3}' /proc/$1/stat 2>/dev/null)" = Z ]
}
mkdir -p hold

# Cold, no limits: the packs every later build must match.
"$bin/crowdbake" build lib.json -o ref -q
for c in walker slow runner; do "$bin/crowdbake" verify ref/$c.crowdpack >/dev/null; done
echo "ok: the library builds whole without limits"

# Past --job-max-seconds (the slow job held past it): it is killed, the two others are written,
# exit 1. The quick ones' manifest limits (over the command line's) keep a sanitizer build's
# slower jobs alive.
library '' ', "limits": {"seconds": 600}' > quick.json
hold
rc=0; "$bin/crowdbake" build quick.json -o t1 --cache t1c --job-max-seconds 1.5 -q 2>err.txt || rc=$?
[ $rc = 1 ] || fail "a job past its time limit: exit $rc, expected 1"
[[ "$(status t1/build.report.json slow)" == "failed slow: mesh: ran "*" s, over --job-max-seconds 1.5 s: killed" ]] ||
  fail "time limit not reported: $(status t1/build.report.json slow)"
cmp t1/walker.crowdpack ref/walker.crowdpack && cmp t1/runner.crowdpack ref/runner.crowdpack
[ ! -e t1/slow.crowdpack ] || fail "the killed character left a pack"
grep -q 'slow: FAILED: slow: mesh: ran' err.txt || fail "quiet build hid the failure: $(cat err.txt)"
echo "ok: $(status t1/build.report.json slow)"

# Past its manifest's memory limit (the command line sets none).
library ', "limits": {"memory_mib": 120}' '' heavy.glb > mem.json
rc=0; "$bin/crowdbake" build mem.json -o t2 --cache t1c -q 2>/dev/null || rc=$?
[ $rc = 1 ] || fail "a job past its memory limit: exit $rc, expected 1"
[[ "$(status t2/build.report.json slow)" == *"over --job-max-memory 120 MiB: stopped"* ]] ||
  fail "memory limit not reported: $(status t2/build.report.json slow)"
cmp t2/walker.crowdpack ref/walker.crowdpack && cmp t2/runner.crowdpack ref/runner.crowdpack
echo "ok: $(status t2/build.report.json slow)"
# The same cache with looser limits: the failures were not cached, the job runs and succeeds.
"$bin/crowdbake" build lib.json -o t3 --cache t1c --job-max-seconds 600 -q
cmp t3/slow.crowdpack ref/slow.crowdpack
grep -q '"run": 2,' t3/build.report.json || fail "looser limits: expected the slow character's 2 jobs run"
echo "ok: a build with looser limits on the same cache runs the job the others stopped"

# A limit that is not a number: the manifest's usual FILE:LINE:COLUMN error.
printf '{"name": "a", "body": "s/humanoid.glb",\n "limits": {"seconds": "ten"}}\n' > bad.json
rc=0; "$bin/crowdbake" build bad.json -o bad.crowdpack 2>err.txt || rc=$?
[ $rc = 1 ] && grep -q 'bad.json:2:13: /limits/seconds: expected a number' err.txt ||
  fail "bad limit: exit $rc: $(cat err.txt)"
echo "ok: $(cat err.txt)"

# The build's own --max-seconds (a build has none by default; the slow job held past it): it
# stops, any pack written before it is whole and kept, nothing is half-written, and the slow
# character has no pack.
hold
rc=0; "$bin/crowdbake" build quick.json -o t4 --cache t4c --max-seconds 1.5 -q 2>err.txt || rc=$?
[ $rc = 1 ] && grep -q 'over --max-seconds 1.5 s: stopped, the packs written before it kept' err.txt ||
  fail "the build's own time limit: exit $rc: $(cat err.txt)"
for p in t4/*.crowdpack; do [ -e "$p" ] && cmp "$p" "ref/$(basename "$p")"; done
[ ! -e t4/slow.crowdpack ] && [ -z "$(find t4 -name '*.tmp-*')" ] || fail "a stopped build left $(ls t4)"
echo "ok: $(cat err.txt) ($(ls t4 | grep -c crowdpack || true) packs kept)"

# SIGKILL of the slow job's process: it is reported and run once more; every pack as cold.
hold
"$bin/crowdbake" build lib.json -o t4 --cache t4c -q &
build=$!
kill -KILL "$(held $build)"
wait $build || fail "a job killed from outside once: the build failed"
python3 - t4/build.report.json <<'PY' || fail "the retry is not in the report"
import json, sys
jobs = [j for c in json.load(open(sys.argv[1]))['characters'] for j in c['jobs']]
retried = [j for j in jobs if j.get('retried_after')]
assert len(retried) == 1 and retried[0]['label'] == 'slow: mesh', retried
assert retried[0]['retried_after'] == 'killed by signal 9 (Killed)', retried
PY
for c in walker slow runner; do cmp t4/$c.crowdpack ref/$c.crowdpack; done
[ -z "$(find t4c -name '*.tmp-*')" ] || fail "the killed job left temporary files"
echo "ok: a job killed by SIGKILL ran again; packs as cold, no temporary file left"

# The build itself killed: its job (held, so it would wait for ever) ends with it, not left
# waiting for no one.
hold
"$bin/crowdbake" build lib.json -o t6 --cache t6c -q &
build=$!
job=$(held $build)
kill -KILL $build
wait $build 2>/dev/null || true
for _ in $(seq 600); do ended "$job" && break; sleep 0.05; done
ended "$job" || fail "the job $job outlived its build by 30 s"
echo "ok: a job ends with its build"

# SIGINT mid-build: exit 130, nothing torn; the next build runs only what had not finished.
hold
"$bin/crowdbake" build lib.json -o t5 --cache t5c --jobs 1 -q 2>err.txt &
build=$!
held $build >/dev/null
kill -INT $build
rc=0; wait $build || rc=$?
[ $rc = 130 ] || fail "an interrupted build exited $rc, expected 130: $(cat err.txt)"
grep -q 'interrupted: .* jobs are in the cache' err.txt || fail "no interrupt line: $(cat err.txt)"
[ -z "$(find t5 t5c -name '*.tmp-*')" ] || fail "an interrupt left temporary files"
[ ! -e t5/slow.crowdpack ] || fail "the interrupted character left a pack"
"$bin/crowdbake" build lib.json -o t5 --cache t5c -q
python3 - t5/build.report.json <<'PY' || fail "the resumed build ran finished jobs again"
import json, sys
r = json.load(open(sys.argv[1]))
ran = sorted(j['label'] for c in r['characters'] for j in c['jobs'] if not j['cached'])
assert 'walker: mesh' not in ran and 'slow: mesh' in ran, ran
PY
for c in walker slow runner; do cmp t5/$c.crowdpack ref/$c.crowdpack; done
echo "ok: an interrupted build: exit 130, the next one resumed; packs as cold"

# cache gc to half the size while a second build runs against the cache (its slow job held until
# the gc ends): both succeed; what gc removed is baked again, to the same bytes.
"$bin/crowdbake" build lib.json -o g1 --cache g -q
find g -name '*.part' -exec touch -d '1 hour ago' {} + # last used an hour ago
"$bin/crowdbake" cache stats g
total=$("$bin/crowdbake" cache stats g --json | python3 -c 'import json,sys; print(json.load(sys.stdin)["bytes"])')
cat > second.json <<'JSON'
{"characters": [
  {"name": "runner", "body": "s/humanoid.glb", "clips": ["run"], "lod": {"floor": 0.1}},
  {"name": "slow2", "body": "s/humanoid.glb", "clips": ["run"], "anim": {"fps": 30, "store": "both"}}
]}
JSON
hold
"$bin/crowdbake" build second.json -o g2 --cache g -q &
build=$!
held $build >/dev/null
"$bin/crowdbake" cache gc g --max-size $((total / 2)) | tee gc.txt
release
wait $build || fail "the build beside a gc failed"
cmp g2/runner.crowdpack ref/runner.crowdpack
after=$("$bin/crowdbake" cache stats g --json | python3 -c 'import json,sys; print(json.load(sys.stdin)["by_kind"])')
grep -q 'removed [1-9]' gc.txt || fail "gc removed nothing: $(cat gc.txt)"
"$bin/crowdbake" build lib.json -o g3 --cache g -q
for c in walker slow runner; do cmp g3/$c.crowdpack ref/$c.crowdpack; done
grep -q '"run": [1-9]' g3/build.report.json || fail "nothing was baked again after the gc"
echo "ok: gc to half beside a build: both succeed, packs as cold (after the gc: $after)"
rc=0; "$bin/crowdbake" cache gc g --max-size 10X 2>err.txt || rc=$?
[ $rc = 2 ] && grep -q "max-size: '10X' is not a size" err.txt || fail "bad size: $rc $(cat err.txt)"

# A Slurm task whose dependency's part left the cache between the stages (a gc) bakes it again:
# the tasks run here by hand, without a cluster, as the arrays would run them.
cat > pair.json <<'JSON'
{"characters": [
  {"name": "walker", "body": "s/humanoid.glb", "clips": ["walk"]},
  {"name": "runner", "body": "s/humanoid.glb", "clips": ["run"], "lod": {"floor": 0.1}}
]}
JSON
"$bin/crowdbake" build pair.json -o s1 --cache s1c --emit-slurm s1s --max-array-size 10 -q
"$bin/crowdbake" build-task s1s/plan.json 0 0 >/dev/null
rm $(grep -l '"mesh"' s1c/*/*.figs | sed 's/\.figs$//')
"$bin/crowdbake" build-task s1s/plan.json 1 0 >/dev/null
"$bin/crowdbake" build-task s1s/plan.json collect >/dev/null
for c in walker runner; do cmp s1/$c.crowdpack ref/$c.crowdpack; done
echo "ok: a Slurm task bakes again a dependency that left the cache; packs as cold"
