#!/usr/bin/env bash
# crowdbake pose speed: the time per posed time after loading, for CesiumMan (3,273 vertices) and
# CesiumMan's primitive repeated 10 times (32,730 vertices, one skin), as binary PLY files and as
# one PC2. Per time = (T(N times) - T(1 time)) / (N - 1): loading and the first time cancel.
# Usage: tests/bench/pose_bench.sh [OUT]
set -euo pipefail
cd "$(dirname "$0")/../.."
out=${1:-out/bench}/pose
mkdir -p "$out"
model=../shared/assets/gltf/CesiumMan/CesiumMan.glb
[ -f "$model" ] || { echo "needs $model" >&2; exit 1; }
python3 - "$model" "$out/CesiumMan_x10.glb" <<'PY'
import json, struct, sys
data = open(sys.argv[1], 'rb').read()
n = struct.unpack_from('<I', data, 12)[0]
gltf = json.loads(data[20:20 + n])
mesh = gltf['meshes'][0]
first = mesh['primitives'][0]
for _ in range(9):  # new accessors over the same data: distinct vertices to the importer
    prim = json.loads(json.dumps(first))
    for name, a in prim['attributes'].items():
        gltf['accessors'].append(dict(gltf['accessors'][a])); prim['attributes'][name] = len(gltf['accessors']) - 1
    mesh['primitives'].append(prim)
text = json.dumps(gltf).encode(); text += b' ' * (-len(text) % 4)
rest = data[20 + n:]
out = struct.pack('<4sII', b'glTF', 2, 20 + len(text) + len(rest)) + struct.pack('<I4s', len(text), b'JSON')
open(sys.argv[2], 'wb').write(out + text + rest)
PY
now() { date +%s.%N; }
times() { python3 -c "import sys; n=int(sys.argv[1]); print(','.join('%.4f' % (2.0 * k / n) for k in range(n)))" "$1"; }
printf '%-16s %9s %6s %16s %16s\n' model vertices format "ms per time" "ms load + 1"
for glb in "$model" "$out/CesiumMan_x10.glb"; do
  name=$(basename "$glb" .glb)
  build/bin/crowdbake anim "$glb" -o "$out/$name.crowdpack" -q
  vertices=$(build/bin/crowdbake inspect "$out/$name.crowdpack" | awk '/^MESH/ {m=1} m && /vertices:/ {print $2; exit}')
  for ext in ply pc2; do
    t0=$(now); build/bin/crowdbake pose "$out/$name.crowdpack" --time 0.5 -o "$out/one.$ext" -q; t1=$(now)
    build/bin/crowdbake pose "$out/$name.crowdpack" --times "$(times 101)" -o "$out/many.$ext" -q; t2=$(now)
    python3 -c "import sys; a, b, c = map(float, sys.argv[1:4]); print('%-16s %9s %6s %16.2f %16.1f' % (sys.argv[4], sys.argv[5], sys.argv[6], ((c - b) - (b - a)) / 100 * 1e3, (b - a) * 1e3))" \
      "$t0" "$t1" "$t2" "$name" "$vertices" "$ext"
    rm -f "$out"/many*.ply
  done
done
