#!/usr/bin/env bash
# crowdbake pose: the files it writes (PLY binary and ASCII, OBJ, PC2) hold the mesh the player
# draws (the pack's vertex and triangle counts, an outfit's sub-meshes, a LOD cut) skinned at
# the asked time, each vertex naming its glTF source through LOD reordering and outfit merges;
# and its failure modes: unknown clip or outfit, a bad time, a LOD cut out of
# range, a pack without a skeleton, a truncated pack, an output folder that does not exist.
set -euo pipefail
. "$(dirname "$(realpath "$0")")/skip.sh"
bin=$1 work=$2 root=${3:-}
rm -rf "$work" && mkdir -p "$work" && cd "$work"
"$bin/crowdbake" samples --no-cloth --out s >/dev/null
"$bin/crowdbake" lod s/humanoid.glb -o h.crowdpack -q
fail() { echo "FAIL: $*" >&2; exit 1; }
expect_error() { # expect_error CODE PATTERN command...
  local code=$1 pattern=$2; shift 2
  local rc=0; "$@" 2>err.txt >/dev/null || rc=$?
  [ $rc = "$code" ] || fail "$* exited $rc, expected $code"
  grep -Eq "$pattern" err.txt || fail "$*: expected '$pattern' in: $(cat err.txt)"
  [ "$(wc -l < err.txt)" = 1 ] || fail "$*: more than one line: $(cat err.txt)"
  echo "ok: $(cat err.txt)"
}
pose() { "$bin/crowdbake" pose h.crowdpack "$@"; }

pose --clip walk --time 0.25 -o walk.ply
pose --clip walk --time 0.25 -o walk_ascii.ply --ascii
pose --clip walk --time 0.25 -o walk.obj
pose --clip walk --time 0.25 -o walk.glb
pose --clip walk --times 0,0.25,0.5 -o walk.pc2
pose --clip walk --times 0,0.25 -o many.ply
pose --clip walk --time 0.25 --lod 2000 -o cut.ply
"$bin/crowdbake" anim s/humanoid.glb -o a.crowdpack -q
"$bin/crowdbake" pose a.crowdpack --clip walk --time 0.25 -o anim.ply --ascii
"$bin/crowdbake" inspect h.crowdpack --json > h.json
python3 - h.json <<'PY'
import json, struct, sys

def ply(path):
    data = open(path, 'rb').read()
    end = data.index(b'end_header\n') + len(b'end_header\n')
    header = data[:end].decode().split('\n')
    nv = int(next(l for l in header if l.startswith('element vertex')).split()[2])
    nf = int(next(l for l in header if l.startswith('element face')).split()[2])
    if 'format ascii 1.0' in header:
        rows = data[end:].decode().split('\n')
        verts = [tuple(map(float, r.split()[:3])) for r in rows[:nv]]
        sources = [tuple(map(int, r.split()[6:])) for r in rows[:nv]]
        faces = [tuple(map(int, r.split()[1:])) for r in rows[nv:nv + nf]]
    else:
        verts = [struct.unpack_from('<3f', data, end + 44 * i) for i in range(nv)]
        sources = [struct.unpack_from('<5i', data, end + 44 * i + 24) for i in range(nv)]
        at = end + 44 * nv
        faces = []
        for _ in range(nf):
            assert data[at] == 3
            faces.append(struct.unpack_from('<3I', data, at + 1)); at += 13
        assert at == len(data), 'trailing bytes'
    assert all(max(f) < nv for f in faces)
    assert all(len(s) == 5 for s in sources)
    ply.sources = sources
    return verts, faces

pack = json.load(open(sys.argv[1]))
mesh = next(c['content'] for c in pack['chunks'] if c['type'] == 'MESH')
vertices, triangles = mesh['vertices'], mesh['triangles']
v, f = ply('walk.ply')
assert len(v) <= vertices and len(f) == triangles, (len(v), len(f), vertices, triangles)
va, fa = ply('walk_ascii.ply')
assert fa == f and max(abs(a - b) for p, q in zip(v, va) for a, b in zip(p, q)) < 1e-6
obj = open('walk.obj').read().split('\n')
assert sum(l.startswith('v ') for l in obj) == len(v) and sum(l.startswith('f ') for l in obj) == triangles
first = [tuple(map(float, l.split()[1:])) for l in obj if l.startswith('v ')][0]
assert max(abs(a - b) for a, b in zip(first, v[0])) < 1e-6
glb = open('walk.glb', 'rb').read()
n = struct.unpack_from('<I', glb, 12)[0]
gltf = json.loads(glb[20:20 + n])
binary = glb[28 + n:]
acc = gltf['accessors']
assert acc[0]['count'] == len(v) and acc[2]['count'] == 3 * triangles, acc
assert struct.unpack_from('<3f', binary, 0) == v[0], 'the .glb and the .ply differ'
cut_v, cut_f = ply('cut.ply')
assert len(cut_v) <= 2000 and len(cut_f) < triangles, (len(cut_v), len(cut_f))
# The LOD pack reorders vertices (and splits some where its repairs need copies); each keeps its
# glTF source: the anim pack (import order) draws the same source vertex at the same place.
lod_sources = (ply('walk.ply'), ply.sources)[1]
anim_v, _ = ply('anim.ply')
at = {s: p for s, p in zip(ply.sources, anim_v)}
assert all(s in at for s in lod_sources)
assert all(s[0] == 0 and min(s) >= 0 for s in lod_sources), 'a vertex without its source'
reordered = sum(s[4] != k for k, s in enumerate(lod_sources))
assert reordered > 0, 'the LOD pack kept import order'
apart = max(abs(a - b) for s, p in zip(lod_sources, v) for a, b in zip(p, at[s]))
assert apart < 1e-5, apart
p0, _ = ply('many_0001.ply'); p1, _ = ply('many_0002.ply')
assert p1 == v and p0 != v, 'the pose does not follow the time'
pc2 = open('walk.pc2', 'rb').read()
assert pc2[:12] == b'POINTCACHE2\0'
version, points, start, spacing, samples = struct.unpack_from('<iiffi', pc2, 12)
assert (version, points, samples) == (1, len(v), 3) and abs(spacing - 0.25) < 1e-6
assert len(pc2) == 32 + 12 * points * samples
second = [struct.unpack_from('<3f', pc2, 32 + 12 * (points + i)) for i in range(points)]
assert second == v, 'the .pc2 sample at 0.25 s differs from the .ply at 0.25 s'
moved = max(abs(a - b) for p, q in zip(p0, v) for a, b in zip(p, q))
print(f'ok: {len(v)} vertices (of the pack\'s {vertices}: those triangles use) and {triangles} triangles in PLY (binary, ASCII), glTF, OBJ and PC2; '
      f'the LOD cut at 2000 vertices draws {len(cut_v)} and {len(cut_f)} triangles; '
      f'vertices move up to {moved:.3f} units from 0 to 0.25 s; '
      f'all {len(lod_sources)} in LOD order ({reordered} moved from import order, {len(lod_sources) - len(set(lod_sources))} split copies) '
      f'sit where the import-order pack puts their source')
PY

validator=$root/.tools/node_modules/gltf-validator
if [ -n "$root" ] && [ -d "$validator" ] && command -v node >/dev/null; then
  node "$root/tests/scripts/validate.js" "$validator" walk.glb
else
  skip_part "the Khronos validator is not installed (./run test installs it): walk.glb not validated"
fi

# A clothed pack draws the chosen outfit's sub-meshes only.
"$bin/crowdbake" outfits s/humanoid.glb --outfit s/outfit_dress.glb --outfit s/outfit_shirt_trousers.glb \
  -o c.crowdpack --frame-step 30 --rays 8 --points 1 -q
"$bin/crowdbake" pose c.crowdpack --outfit dress -o dress.ply
"$bin/crowdbake" pose c.crowdpack --outfit shirt_trousers -o shirt.ply
[ "$(grep -a -m1 'element face' dress.ply)" != "$(grep -a -m1 'element face' shirt.ply)" ] ||
  fail "two outfits drew the same triangles"
echo "ok: dress $(grep -a -m1 'element face' dress.ply), shirt_trousers $(grep -a -m1 'element face' shirt.ply)"
"$bin/crowdbake" pose c.crowdpack --outfit dress -o dress_ascii.ply --ascii
"$bin/crowdbake" pose c.crowdpack --outfit shirt_trousers -o shirt_ascii.ply --ascii
files() { sed '1,/end_header/d' "$1" | awk 'NF == 11 { print $7 }' | sort -u | tr '\n' ' '; }
[ "$(files dress_ascii.ply)" = "0 1 " ] && [ "$(files shirt_ascii.ply)" = "0 2 " ] ||
  fail "outfit vertex sources: dress from files $(files dress_ascii.ply), shirt from $(files shirt_ascii.ply)"
echo "ok: the dress's vertices come from files 0 (body) and 1, shirt_trousers's from 0 and 2"

# A pack without clips draws the bind pose: the same humanoid with its animations taken out.
python3 - s/humanoid.glb still.glb <<'PY'
import json, struct, sys
data = open(sys.argv[1], 'rb').read()
n = struct.unpack_from('<I', data, 12)[0]
gltf = json.loads(data[20:20 + n]); del gltf['animations']
text = json.dumps(gltf).encode(); text += b' ' * (-len(text) % 4)
rest = data[20 + n:]
out = struct.pack('<4sII', b'glTF', 2, 20 + len(text) + len(rest)) + struct.pack('<I4s', len(text), b'JSON')
open(sys.argv[2], 'wb').write(out + text + rest)
PY
"$bin/crowdbake" anim still.glb -o still.crowdpack -q
"$bin/crowdbake" pose still.crowdpack --time 0.5 -o still.ply
"$bin/crowdbake" pose still.crowdpack --time 0 -o still0.ply
cmp still.ply still0.ply || fail "a pack without clips moved with time"
echo "ok: a pack without clips: the bind pose at any time"

# Failure modes: one line each, nothing written.
expect_error 1 "no clip named 'dance' \(clips: walk, run, idle\)" pose --clip dance -o x.ply
expect_error 1 "no outfit named 'skirt' \(outfits: dress, shirt_trousers\)" \
  "$bin/crowdbake" pose c.crowdpack --outfit skirt -o x.ply
expect_error 2 "time nan: must be a finite number" pose --time nan -o x.ply
expect_error 2 "time -1: must be a finite number" pose --times 0,-1 -o x.ply
expect_error 2 "evenly spaced" pose --times 0,0.1,0.5 -o x.pc2
expect_error 1 "LOD cut at 10 vertices: the pack has [0-9]+\.\.[0-9]+" pose --lod 10 -o x.ply
expect_error 1 "the folder missing does not exist" pose -o missing/x.ply
expect_error 2 "expected a .ply, .glb, .obj or .pc2 file" pose -o x.stl
head -c 100000 h.crowdpack > truncated.crowdpack
expect_error 1 "truncated" "$bin/crowdbake" pose truncated.crowdpack -o x.ply
"$bin/crowdbake" impostor s/humanoid.glb -o i.crowdpack --frames 2 --views 4x2 --texels 16 -q
expect_error 1 "required chunk SKEL is missing" "$bin/crowdbake" pose i.crowdpack -o x.ply
[ ! -e x.ply ] && [ ! -e x.pc2 ] && [ ! -d missing ] || fail "a failed pose wrote a file"
pose --clip walk --time 3 -o wrapped.ply 2>err.txt
grep -q "past clip 'walk' (1 s): the player wraps it to" err.txt || fail "no wrap warning: $(cat err.txt)"
echo "ok: $(cat err.txt)"
# Many times past the clip's end: one warning line, not one per time.
pose --clip walk --times 0.5,1.5,2.5,3.5 -o series.pc2 2>err.txt
[ "$(wc -l < err.txt)" = 1 ] && grep -q "3 of 4 times are past clip 'walk' (1 s): the player wraps them" err.txt ||
  fail "not one wrap warning for a series: $(cat err.txt)"
echo "ok: $(cat err.txt)"
end_skipped_parts
