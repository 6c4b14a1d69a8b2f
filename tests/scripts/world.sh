#!/usr/bin/env bash
# crowdplay with a world: samples/scenes/village.json's agents walk the sample
# village's terrain and draw (headless, Mesa under Xvfb); a walker casts its shadow on the ground;
# a behaviour image of another size than the terrain's grid, one oversized, one cut, a missing
# terrain pack and a FIFO
# for an image are one-line errors.
set -euo pipefail
. "$(dirname "$(realpath "$0")")/skip.sh"
command -v Xvfb >/dev/null || skip "Xvfb is not installed (apt-get install xvfb)"
bin=$1 work=$2 src=$3
xvfb=$(dirname "$(realpath "$0")")/xvfb.sh # the player under a fresh X display
rm -rf "$work" && mkdir -p "$work/samples/scenes" "$work/out" && cd "$work"
fail() { echo "FAIL: $*" >&2; exit 1; }
cb() { "$bin/crowdbake" "$@"; }
cb samples --no-cloth --out out/samples >/dev/null
cb lod out/samples/humanoid.glb -o out/humanoid.crowdpack --poses 2 -q
cb impostor out/samples/humanoid.glb -o out/humanoid_walk.impostor.crowdpack --clip walk \
  --frames 4 --views 8x2 --texels 32 --mirror -q
cb terrain out/samples/village.glb -o out/village.crowdpack -q
cp "$src/samples/scenes/village.json" samples/scenes/
play() { # play SCENE crowdplay-options...: exit code, stderr in err.txt
  local rc=0
  "$xvfb" "$bin/crowdplay" "$@" --headless --size 320x180 \
    > out.txt 2> err.txt || rc=$?
  echo $rc
}
rc=$(play samples/scenes/village.json --instances 400 --frames 2 --time 25 --screenshot v.png \
  --stats v.json)
[ "$rc" = 0 ] || fail "the village did not draw (exit $rc): $(cat err.txt)"
[ -s v.png ] || fail "no screenshot"
python3 - <<'PY'
import json
s = json.load(open('v.json'))['summary']
assert s['instances'] == 400 and s['visible'] > 0 and s['agents_ms'] > 0, s
print('ok: village, 400 agents:', {k: s[k] for k in ('instances', 'visible', 'impostors', 'agents_ms')})
PY
# One walker on the square at its spawn, seen from the side its shadow falls to (the light is
# the terrain's, 0.4,1,0.3): the paving under its shadow is darkened (x 0.55), and nothing else
# in view is.
python3 - <<'PY'
import json
s = json.load(open('samples/scenes/village.json'))
s['world'].update({'spawn': [{'min': [0.1, 0.1], 'max': [0.1, 0.1], 'count': 1}], 'runners': 0})
del s['world']['behaviour'], s['world']['callbacks']
s['camera'] = {'position': [-2.5, 2.5, -2.5], 'target': [0, 0.3, 0], 'fov': 50}
json.dump(s, open('samples/scenes/one.json', 'w'))
PY
rc=$(play samples/scenes/one.json --frames 1 --time 0 --screenshot one.png)
[ "$rc" = 0 ] || fail "one walker (exit $rc): $(cat err.txt)"
python3 - <<'PY'
import struct, zlib
data = open('one.png', 'rb').read()
w, h, depth, kind = struct.unpack('>IIBB', data[16:26])
chunks, at = b'', 8
while at < len(data):
    n, tag = struct.unpack('>I4s', data[at:at + 8])
    if tag == b'IDAT': chunks += data[at + 8:at + 8 + n]
    at += 12 + n
raw, bpp = zlib.decompress(chunks), {2: 3, 6: 4}[kind]
rows, prev, i = [], bytearray(w * bpp), 0
for y in range(h):
    f, line = raw[i], bytearray(raw[i + 1:i + 1 + w * bpp]); i += 1 + w * bpp
    for x in range(len(line)):
        a = line[x - bpp] if x >= bpp else 0; b = prev[x]; c = prev[x - bpp] if x >= bpp else 0
        p = a + b - c; pr = a if abs(p - a) <= abs(p - b) and abs(p - a) <= abs(p - c) else b if abs(p - b) <= abs(p - c) else c
        line[x] = (line[x] + [0, a, b, (a + b) // 2, pr][f]) & 255
    rows.append(line); prev = line
def count(lo, hi):
    return sum(1 for r in rows for x in range(w) if all(lo[k] <= r[x * bpp + k] <= hi[k] for k in range(3)))
lit = count((136, 132, 122), (156, 152, 142))    # the paving lit: 0.926 x its colour
shade = count((70, 68, 63), (90, 88, 83))        # x 0.55: under a shadow
assert lit > 10000 and shade > 100, (lit, shade)
print(f'ok: one walker\'s shadow: {shade} darkened paving pixels against {lit} lit')
PY
cb export out/humanoid.crowdpack --images tex >/dev/null
expect_error() { # expect_error NAME SED PATTERN: the village scene, edited by SED, exits 1 with PATTERN
  sed "$2" samples/scenes/village.json > "samples/scenes/$1.json"
  local rc; rc=$(play "samples/scenes/$1.json" --instances 10 --frames 1)
  # one crowdplay line; beside it only xvfb.sh's report of the exit (no decoder's own lines)
  [ "$rc" = 1 ] && grep -q "$3" err.txt && [ "$(grep -c '^crowdplay: ' err.txt)" = 1 ] &&
    ! grep -qv -e '^crowdplay: error: ' -e '^xvfb.sh: ' -e '^  ' -e '^$' err.txt ||
    fail "$1 (exit $rc, expected 1 and one line): $(cat err.txt)"
  echo "ok: $(cat err.txt)"
}
expect_error wrong_size 's|../../out/samples/village_behaviour.png|../../tex/diffuse.png|' \
  "diffuse.png: the behaviour image is 256x256 pixels; the terrain's grid is 320x320 cells"
expect_error no_terrain 's|../../out/village.crowdpack|../../out/none.crowdpack|' \
  "does not exist (bake it: crowdbake terrain)"
# A world image that is not a regular file (a FIFO with no writer blocked crowdplay for good).
mkfifo fifo.png
expect_error fifo 's|../../out/samples/village_behaviour.png|../../fifo.png|' \
  "fifo.png: not a regular file (a FIFO): nothing read"
# A behaviour image whose PNG header claims 60000x60000 pixels, and the real one cut in half:
# refused before decoding, in one line (no decoder's own output beside it).
python3 - out/samples/village_behaviour.png <<'PY'
import struct, sys, zlib
chunk = lambda kind, data: struct.pack('>I', len(data)) + kind + data + struct.pack('>I', zlib.crc32(kind + data))
open('big.png', 'wb').write(b'\x89PNG\r\n\x1a\n' + chunk(b'IHDR', struct.pack('>IIBBBBB', 60000, 60000, 8, 2, 0, 0, 0)) +
                            chunk(b'IDAT', zlib.compress(b'\0' * 4096)) + chunk(b'IEND', b''))
real = open(sys.argv[1], 'rb').read()
open('cut.png', 'wb').write(real[:len(real) // 2])
PY
expect_error oversized 's|../../out/samples/village_behaviour.png|../../big.png|' \
  "big.png: expected an RGB or RGBA image of at most [0-9]* pixels a side: cannot decode (PNG 60000x60000 is outside 1\.\."
expect_error corrupt 's|../../out/samples/village_behaviour.png|../../cut.png|' \
  "cut.png: expected an RGB or RGBA image .*: cannot decode (PNG chunk IDAT: cut"
echo "world: all checks passed"
