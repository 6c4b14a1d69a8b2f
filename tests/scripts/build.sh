#!/usr/bin/env bash
# crowdbake build: manifests with errors, a library with a failing character, byte identity at
# 1 and 2 workers, warm builds from the cache, a changed setting, a damaged cache entry, two
# builds sharing one cache at once, a disk filling up, and the player drawing a character pack.
set -euo pipefail
. "$(dirname "$(realpath "$0")")/skip.sh"
bin=$1 work=$2
xvfb=$(dirname "$(realpath "$0")")/xvfb.sh # the player under a fresh X display
rm -rf "$work" && mkdir -p "$work" && cd "$work"
"$bin/crowdbake" samples --no-cloth --out s >/dev/null
fail() { echo "FAIL: $*" >&2; exit 1; }
expect_error() { # expect_error PATTERN command...: exit code 1 and PATTERN on stderr
  local pattern=$1; shift
  local rc=0; "$@" 2>err.txt >/dev/null || rc=$?
  [ $rc = 1 ] || fail "$* exited $rc, expected 1"
  grep -Eq "$pattern" err.txt || fail "$*: expected '$pattern' in: $(cat err.txt)"
  echo "ok: $(head -c 160 err.txt)"
}

# Manifest errors name file, line and column.
printf '{"name": "a",\n "body": "missing.glb"}\n' > missing.json
expect_error 'missing.json:2:2: /body: .*missing.glb: cannot open file' \
  "$bin/crowdbake" build missing.json -o a.crowdpack
printf '{"name": "a", "body": "s/humanoid.glb",\n  "lod": {"flor": 0.1}}\n' > unknown.json
expect_error 'unknown.json:2:11: /lod/flor: unknown key' "$bin/crowdbake" build unknown.json -o a.crowdpack
printf '{"name": "a", "body": "s/humanoid.glb",\n  "clips": "walk"}\n' > type.json
expect_error 'type.json:2:3: /clips: expected a list' "$bin/crowdbake" build type.json -o a.crowdpack
printf '{"name": "a", "body": "s/humanoid.glb", "clips": ["sprint"]}\n' > clip.json
expect_error "no clip named 'sprint'" "$bin/crowdbake" build clip.json -o a.crowdpack
# In a library, an inline character's error points at that character, not the first one.
printf '{"characters": [\n  {"name": "a", "body": "s/humanoid.glb"},\n  {"name": "b", "body": "gone.glb"}]}\n' > inline.json
expect_error 'inline.json:3:17: /characters/1/body: .*gone.glb: cannot open file' \
  "$bin/crowdbake" build inline.json -o lib

# A library: two good characters (one with impostors), one whose body is not glTF.
head -c 300 s/humanoid.glb > broken.glb
cat > library.json <<'JSON'
{"characters": [
  {"name": "walker", "body": "s/humanoid.glb", "clips": ["walk"],
   "impostor": {"clips": ["walk"], "frames": 2, "views": "4x2", "texels": 16}},
  {"name": "broken", "body": "broken.glb"},
  {"name": "runner", "body": "s/humanoid.glb", "clips": ["run", "idle"], "lod": {"floor": 0.1}}
]}
JSON
rc=0; "$bin/crowdbake" build library.json -o out1 --jobs 1 -q || rc=$?
[ $rc = 1 ] || fail "a library with a broken character exited $rc, expected 1"
[ -f out1/walker.crowdpack ] && [ -f out1/runner.crowdpack ] || fail "good characters not written"
[ ! -e out1/broken.crowdpack ] || fail "the broken character left a pack"
grep -q '"characters_failed": 1' out1/build.report.json || fail "report does not count the failure"
grep -q '"error": "broken: mesh: .*broken.glb' out1/build.report.json || fail "report does not name the error"
echo "ok: the broken character failed alone"
# A build of the library (its broken character included): exit 1, the failure alone, else the
# test fails with the code.
build1() {
  local rc=0
  "$bin/crowdbake" build "$@" || rc=$?
  [ $rc = 1 ] || fail "crowdbake build $* exited $rc, expected 1 (the broken character alone)"
}
"$bin/crowdbake" verify out1/walker.crowdpack
"$bin/crowdbake" verify out1/runner.crowdpack

# Same bytes at 2 workers (own cache), and a warm build runs nothing.
build1 library.json -o out2 --jobs 2 -q
cmp out1/walker.crowdpack out2/walker.crowdpack
cmp out1/runner.crowdpack out2/runner.crowdpack
echo "ok: byte-identical at --jobs 1 and --jobs 2"
build1 library.json -o out1 --jobs 2 -q
grep -q '"run": 0' out1/build.report.json || fail "warm build ran jobs"
echo "ok: warm build: every good job cached"
# A pack that still has the hash recorded for its link is neither loaded nor written again; an
# altered one is written again from the cache.
[ "$(grep -c '"pack_up_to_date": true' out1/build.report.json)" = 2 ] || fail "warm packs rewritten"
# ... and still reports every good job's figures (each part's figures file in the cache).
python3 - out1/build.report.json <<'PY' || fail "a warm build lost job figures"
import json, sys
r = json.load(open(sys.argv[1]))
jobs = [j for c in r['characters'] for j in c['jobs'] if not j['failed']]
empty = [j['label'] for j in jobs if not j.get('figures')]
assert jobs and not empty, empty
mesh = [j for j in jobs if j['kind'] == 'mesh']
assert mesh and all(j['figures'].get('clips') for j in mesh), 'mesh figures without clips'
PY
printf 'X' | dd of=out1/runner.crowdpack bs=1 seek=5000 conv=notrunc status=none
build1 library.json -o out1 --jobs 2 -q
cmp out1/runner.crowdpack out2/runner.crowdpack || fail "an altered pack was not written again"
[ "$(grep -c '"pack_up_to_date": true' out1/build.report.json)" = 1 ] || fail "up-to-date count"
echo "ok: warm packs left alone, an altered one written again"

# A changed setting reruns only that character's jobs.
sed 's/"floor": 0.1/"floor": 0.2/' library.json > library2.json
build1 library2.json -o out1 --cache out1/.cache -q
grep -q '"run": 2' out1/build.report.json || fail "changing one setting should run 2 jobs (mesh, link)"
cmp out1/walker.crowdpack out2/walker.crowdpack
echo "ok: a changed setting reran runner's mesh and link only"

# A damaged cache entry is detected, reported and rebuilt.
for entry in $(find out2/.cache -name '*.part'); do
  printf 'garbage' | dd of="$entry" bs=1 seek=100 conv=notrunc status=none
done
head -c 200 "$entry" > "$entry.cut" && mv "$entry.cut" "$entry" # and one truncated
rm out2/*.crowdpack # packs still up to date would need no part
build1 library.json -o out2 2>log.txt
grep -q "damaged cache entry rebuilt" log.txt || fail "damaged entry not reported"
cmp out2/walker.crowdpack out1/walker.crowdpack
echo "ok: damaged cache entry rebuilt"

# A .gltf's external buffer is an input like the .gltf itself: in the pack's provenance, and a
# changed buffer reruns the jobs that read it.
mkdir -p split && python3 - s/humanoid.glb split <<'PY'
import json, struct, sys
data = open(sys.argv[1], 'rb').read()
n = struct.unpack_from('<I', data, 12)[0]
gltf, binary = json.loads(data[20:20 + n]), data[28 + n:]
gltf['buffers'][0]['uri'] = 'humanoid data.bin'  # a space: percent-encoded below
json.dump(gltf, open(sys.argv[2] + '/humanoid.gltf', 'w'))
open(sys.argv[2] + '/humanoid data.bin', 'wb').write(binary)
PY
sed -i 's/humanoid data.bin/humanoid%20data.bin/' split/humanoid.gltf
printf '{"name": "split", "body": "split/humanoid.gltf", "clips": ["walk"], "lod": false}\n' > split.json
"$bin/crowdbake" build split.json -o split.crowdpack -q
"$bin/crowdbake" inspect split.crowdpack | grep -q 'humanoid data.bin' ||
  fail "the external buffer is not in the pack's provenance"
python3 - split <<'PY'
import json, struct, sys
g = json.load(open(sys.argv[1] + '/humanoid.gltf'))
view = g['bufferViews'][g['accessors'][g['meshes'][0]['primitives'][0]['attributes']['POSITION']]['bufferView']]
with open(sys.argv[1] + '/humanoid data.bin', 'r+b') as f:  # nudge the first vertex by 1 mm
    f.seek(view.get('byteOffset', 0)); x = struct.unpack('<f', f.read(4))[0]
    f.seek(view.get('byteOffset', 0)); f.write(struct.pack('<f', x + 0.001))
PY
"$bin/crowdbake" build split.json -o split.crowdpack -q --report split.report.json
grep -q '"run": 2' split.report.json || fail "a changed external buffer did not rerun mesh and link"
echo "ok: a .gltf's external buffer is hashed into provenance and the cache key"

# Two builds sharing one cache at once: both complete with identical packs.
"$bin/crowdbake" build library.json -o out3 --cache shared -q & a=$!
"$bin/crowdbake" build library.json -o out4 --cache shared -q & b=$!
rc_a=0 rc_b=0
wait $a || rc_a=$?
wait $b || rc_b=$?
[ $rc_a = 1 ] && [ $rc_b = 1 ] || fail "two builds on one cache exited $rc_a and $rc_b, expected 1 each"
cmp out3/walker.crowdpack out4/walker.crowdpack
cmp out3/runner.crowdpack out4/runner.crowdpack
cmp out3/runner.crowdpack out2/runner.crowdpack
[ -z "$(find shared -name '*.tmp-*')" ] || fail "temporary files left in the cache"
echo "ok: two builds sharing a cache"

# Disk full during a build: a 6 MiB file system (tmpfs, as root) holding the output and the cache,
# filled once a first build is in. Where mounting is not allowed, a file-size limit stands in
# (writes past it fail with EFBIG, as past a full disk with ENOSPC).
mkdir -p full
if mount -t tmpfs -o size=6m tmpfs full 2>/dev/null; then
  trap 'umount "$work/full" 2>/dev/null || true' EXIT
  fill() { dd if=/dev/zero of=full/filler bs=64k status=none 2>/dev/null || true; }
  limited() { "$@"; }
  echo "disk full: a 6 MiB tmpfs"
else
  fill() { :; }
  limited() { (ulimit -f 1; trap '' XFSZ; "$@"); }
  echo "disk full: cannot mount a tmpfs here; a 1 KiB file-size limit stands in"
fi
printf '{"name": "walker", "body": "s/humanoid.glb", "clips": ["walk"], "lod": {"poses": 2}}\n' > full.json
"$bin/crowdbake" build full.json -o full/walker.crowdpack --cache full/cache -q
cp full/walker.crowdpack walker_before.crowdpack
fill
sed -i 's/"poses": 2/"poses": 3/' full.json # new keys: every job runs and writes
rc=0; limited "$bin/crowdbake" build full.json -o full/walker.crowdpack --cache full/cache 2>err.txt || rc=$?
[ $rc = 1 ] || fail "a build on a full disk exited $rc, expected 1"
grep -q 'write failed (disk full?)' err.txt || fail "no clear disk-full error in: $(cat err.txt)"
grep -q "walker: FAILED" err.txt || fail "the summary does not name the failed character"
cmp walker_before.crowdpack full/walker.crowdpack || fail "the earlier pack was damaged"
[ -z "$(find full -name '*.tmp*')" ] || fail "temporary files left: $(find full -name '*.tmp*')"
# The report cannot be written either: its one error comes after the summary, no temp file left.
rc=0; limited "$bin/crowdbake" build full.json -o full/walker.crowdpack --cache cache_elsewhere \
  --report full/r.json 2>err.txt || rc=$?
[ $rc = 1 ] && grep -q 'full/r.json: write failed (disk full?)' err.txt ||
  fail "report on a full disk: exit $rc, $(cat err.txt)"
[ -z "$(find full -name '*.tmp*')" ] || fail "temporary files left: $(find full -name '*.tmp*')"
rm -f full/filler
"$bin/crowdbake" build full.json -o full/walker.crowdpack --cache full/cache -q
"$bin/crowdbake" verify full/walker.crowdpack >/dev/null
sed -i 's/"poses": 3/"poses": 2/' full.json # the first build's parts are still in the cache
"$bin/crowdbake" build full.json -o full/walker.crowdpack --cache full/cache --report r.json -q
grep -q '"run": 0' r.json || fail "the cache lost the first build's parts"
cmp walker_before.crowdpack full/walker.crowdpack
echo "ok: disk full: one clear error, the earlier pack and the cache intact, no temporary files"

# The player draws a character pack without a scene file.
if command -v Xvfb >/dev/null; then
  "$xvfb" "$bin/crowdplay" out1/walker.crowdpack --headless \
    --frames 2 --size 320x240 --screenshot walker.png --stats stats.json
  grep -q '"impostors"' stats.json || fail "no stats"
  [ -s walker.png ] || fail "no screenshot"
  echo "ok: crowdplay drew the character pack"
else
  skip_part "Xvfb is not installed: the player check did not run"
fi
end_skipped_parts
