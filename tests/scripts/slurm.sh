#!/usr/bin/env bash
# crowdbake build --slurm on a single-node cluster started here (slurm_cluster.sh): the sample
# library built through job arrays gives the same pack bytes as the local build; a failing
# character is recorded by its task and reported by the collect job; --emit-slurm writes
# scripts without submitting; a stopped cluster is one clear error. Exit 77 (skip) with the
# reason where the daemons cannot start. The bakes are kept small: every one of them runs three
# times (release only: see tests/CMakeLists.txt).
set -euo pipefail
. "$(dirname "$(realpath "$0")")/skip.sh"
bin=$1 work=$2
here=$(cd "$(dirname "$0")" && pwd)
rm -rf "$work" && mkdir -p "$work" && cd "$work"
cluster=$work/cluster
trap '"$here/slurm_cluster.sh" stop "$cluster"' EXIT
# Six CPUs declared on CI's two cores: the tiny tasks wait on Slurm, not on a core.
rc=0; CPUS=${CPUS:-6} "$here/slurm_cluster.sh" start "$cluster" || rc=$?
[ $rc = 0 ] || skip "the Slurm daemons cannot start here (see above)"
export SLURM_CONF=$cluster/slurm.conf
fail() { echo "FAIL: $*" >&2; exit 1; }

"$bin/crowdbake" samples --no-cloth --out s >/dev/null
head -c 300 s/humanoid.glb > broken.glb
cat > library.json <<'JSON'
{"characters": [
  {"name": "walker", "body": "s/humanoid.glb", "clips": ["walk"],
   "impostor": {"clips": ["walk"], "frames": 2, "views": "4x2", "texels": 16}},
  {"name": "broken", "body": "broken.glb"},
  {"name": "runner", "body": "s/humanoid.glb", "clips": ["run", "idle"],
   "lod": {"floor": 0.1, "poses": 2}},
  {"name": "dressed", "body": "s/humanoid.glb", "clips": ["walk"],
   "outfits": {"dress": "s/outfit_dress.glb"}, "lod": false,
   "visibility": {"frame_step": 8, "rays": 8},
   "impostor": {"clips": ["walk"], "outfits": ["dress"], "frames": 2, "views": "4x2", "texels": 16}}
]}
JSON

# Only the scripts: nothing is submitted and no pack is written.
"$bin/crowdbake" build library.json -o emitted --emit-slurm scripts -q
for f in plan.json stage0.sbatch stage1.sbatch collect.sbatch submit.sh; do
  [ -f "scripts/$f" ] || fail "--emit-slurm did not write $f"
done
grep -q -- '--array=0-1' scripts/stage0.sbatch || fail "stage 0: 6 jobs at 4 per task is 2 tasks"
grep -q 'afterok' scripts/submit.sh || fail "submit.sh has no afterok dependency"
[ -z "$(squeue -h)" ] || fail "--emit-slurm submitted jobs"
[ ! -e emitted/walker.crowdpack ] || fail "--emit-slurm wrote packs"
echo "ok: --emit-slurm writes the plan and scripts, submits nothing"
# Past MaxArraySize a stage is several arrays; per-job limits become the tasks' --time and --mem.
"$bin/crowdbake" build library.json -o emitted --emit-slurm split -q --jobs-per-task 1 \
  --max-array-size 4 --job-max-seconds 600 --job-max-memory 3000
grep -q -- '--array=0-3' split/stage0.sbatch && grep -q -- '--array=0-1' split/stage0.1.sbatch ||
  fail "stage 0: 6 tasks at 4 an array are two arrays of 4 and 2"
grep -q '$((4 + SLURM_ARRAY_TASK_ID))' split/stage0.1.sbatch || fail "the second array's tasks are not offset"
[ ! -e split/stage1.1.sbatch ] || fail "stage 1: 4 tasks fit one array"
grep -q 'afterok:$(IFS=:' split/submit.sh || fail "stage 1 does not wait for every array of stage 0"
grep -q -- '--time=11$' split/stage0.sbatch && grep -q -- '--mem=3000M$' split/stage0.sbatch ||
  fail "per-job limits are not the tasks' --time and --mem: $(cat split/stage0.sbatch)"
echo "ok: a stage past --max-array-size is several arrays; limits are --time and --mem"

# The same library locally and on Slurm (two jobs per task, their own caches): same bytes. Stage
# 0's three tasks are two arrays (--max-array-size 2).
rc=0; "$bin/crowdbake" build library.json -o local --jobs 2 -q || rc=$?
[ $rc = 1 ] || fail "local build exited $rc, expected 1 (one broken character)"
rc=0; "$bin/crowdbake" build library.json -o farm --slurm --jobs-per-task 2 --cpus-per-task 1 \
  --max-array-size 2 2>farm.txt || rc=$?
cat farm.txt
[ $rc = 1 ] || fail "Slurm build exited $rc, expected 1 (one broken character)"
for c in walker runner dressed; do
  cmp "local/$c.crowdpack" "farm/$c.crowdpack" || fail "$c differs between local and Slurm"
done
[ ! -e farm/broken.crowdpack ] || fail "the broken character left a pack"
grep -q '"characters_failed": 1' farm/build.report.json || fail "report does not count the failure"
grep -q '"error": "broken: mesh: .*broken.glb' farm/build.report.json ||
  fail "report does not name the failure"
grep -q 'broken: link: FAILED: not run: broken: mesh failed' farm/.slurm/logs/stage1-*.log ||
  fail "the link task did not record its failed dependency"
echo "ok: Slurm packs byte-identical to the local build; the broken character failed alone"

# Again on Slurm: the tasks find every part in the cache. --max-seconds bounds crowdbake's own
# work, not the wait for the cluster (which takes longer than 4 s here).
rc=0; "$bin/crowdbake" build library.json -o farm --slurm --jobs-per-task 8 --cpus-per-task 1 -q \
  --max-seconds 4 || rc=$?
[ $rc = 1 ] || fail "second Slurm build exited $rc"
grep -q ': cached' farm/.slurm/logs/stage0-0.log || fail "second Slurm build ran its jobs again"
echo "ok: a second Slurm build takes every part from the cache"

# The daemons stopped: one clear error, nothing written.
"$here/slurm_cluster.sh" stop "$cluster"
rc=0; "$bin/crowdbake" build library.json -o down --slurm -q 2>down.txt || rc=$?
[ $rc = 1 ] || fail "build with the cluster down exited $rc, expected 1"
[ "$(wc -l < down.txt)" = 1 ] || fail "expected one line, got: $(cat down.txt)"
grep -q 'crowdbake: error: the Slurm build wrote no report: sbatch: error: .*contact slurm controller' \
  down.txt || fail "unclear error: $(cat down.txt)"
[ ! -e down/walker.crowdpack ] || fail "a pack was written with the cluster down"
echo "ok: $(cat down.txt)"
