#!/usr/bin/env python3
"""farm_library.py N OUT SAMPLES [--tiny QUAD.gltf]: a library of N distinct characters for the
farm benchmarks (tests/bench/farm_scale.sh, slurm_bench.sh), from crowdbake's samples (SAMPLES:
`crowdbake samples --no-cloth`).

--tiny: each character is the skinned quad QUAD.gltf (tests/fuzz/seed_quad.gltf) scaled, without
LOD: two jobs of a few milliseconds each, to measure what a farm adds to a job.

Each character's body is the sample humanoid with its own proportions (the skeleton root scaled
by a width and a height of its own), so no two characters share a job key; clips cycle through
the seven non-empty subsets of walk, run and idle; every tenth wears the dress (scaled with it)
and every fifth has impostors of its first clip. Writes OUT/library.json, OUT/bodies/*.glb."""
import json
import os
import struct
import sys

n, out, samples = int(sys.argv[1]), sys.argv[2], sys.argv[3]
tiny = sys.argv[5] if len(sys.argv) > 5 and sys.argv[4] == '--tiny' else None
os.makedirs(os.path.join(out, 'bodies'), exist_ok=True)


def read_glb(path):
    data = open(path, 'rb').read()
    length = struct.unpack_from('<I', data, 12)[0]
    return json.loads(data[20:20 + length]), data[20 + length:]


def write_glb(path, doc, rest):
    text = json.dumps(doc, separators=(',', ':')).encode()
    text += b' ' * ((4 - len(text) % 4) % 4)
    body = struct.pack('<I4s', len(text), b'JSON') + text + rest
    open(path, 'wb').write(struct.pack('<4sII', b'glTF', 2, 12 + len(body)) + body)


def scaled(src, dst, width, height):
    doc, rest = read_glb(src)
    for node in doc['nodes']:
        if node.get('name') == 'root':
            node['scale'] = [width, height, width]
    write_glb(dst, doc, rest)


subsets = [['walk'], ['run'], ['idle'], ['walk', 'run'], ['walk', 'idle'], ['run', 'idle'],
           ['walk', 'run', 'idle']]
def tiny_character(i, width, height):
    doc = json.load(open(tiny))
    doc['nodes'][0]['scale'] = [width, height, width]
    body = 'bodies/q%04d.gltf' % i
    json.dump(doc, open(os.path.join(out, body), 'w'))
    return {'name': 'q%04d' % i, 'body': body, 'lod': False}


characters = []
for i in range(n):
    # Low-discrepancy proportions: distinct for every i, spread over the range.
    width = round(0.85 + 0.3 * ((i * 0.6180339887) % 1), 6)
    height = round(0.9 + 0.2 * ((i * 0.7548776662) % 1), 6)
    if tiny:
        characters.append(tiny_character(i, width, height))
        continue
    name = 'c%04d' % i
    body = 'bodies/%s.glb' % name
    scaled(os.path.join(samples, 'humanoid.glb'), os.path.join(out, body), width, height)
    c = {'name': name, 'body': body, 'clips': subsets[i % len(subsets)], 'lod': {'poses': 4}}
    if i % 10 == 9:
        dress = 'bodies/%s_dress.glb' % name
        scaled(os.path.join(samples, 'outfit_dress.glb'), os.path.join(out, dress), width, height)
        c['outfits'] = {'dress': dress}
        c['visibility'] = {'frame_step': 8, 'rays': 8}
    if i % 5 == 4:
        c['impostor'] = {'clips': c['clips'][:1], 'frames': 2, 'views': '4x2', 'texels': 16}
    characters.append(c)
json.dump({'characters': characters}, open(os.path.join(out, 'library.json'), 'w'), indent=1)
