#!/usr/bin/env python3
# Adds to a GLB's "walk" clip a squash-and-stretch of one joint (9 non-uniform scale keys over
# the clip): a rig where that joint and the joints it carries shear and the rest stay rigid, for
# the animation bake's per-joint matrix fallback (docs/bakes/anim.md, "What qts cannot carry").
#   python3 tests/bench/stretch_joint.py humanoid.glb neck humanoid_neck.glb
#   crowdbake anim humanoid_neck.glb -o p.crowdpack --report r.json   # figures.matrix_joints
import json, math, struct, sys

src, joint_name, out = sys.argv[1], sys.argv[2], sys.argv[3]
b = open(src, 'rb').read()
jlen = struct.unpack_from('<I', b, 12)[0]
g = json.loads(b[20:20 + jlen])
binlen = struct.unpack_from('<I', b, 20 + jlen)[0]
bin_ = bytearray(b[28 + jlen:28 + jlen + binlen])
walk = next(a for a in g['animations'] if a['name'] == 'walk')
times_acc = walk['samplers'][0]['input']
n = g['accessors'][times_acc]['count']
t0, t1 = g['accessors'][times_acc]['min'][0], g['accessors'][times_acc]['max'][0]
keys = 9
times = [t0 + (t1 - t0) * k / (keys - 1) for k in range(keys)]
vals = []
for k in range(keys):
    s = 1 + 0.25 * math.sin(2 * math.pi * k / (keys - 1))
    vals += [1.0, s, 1.0 / s]
while len(bin_) % 4: bin_.append(0)
def add(data, typ, count, mn=None, mx=None):
    off = len(bin_); bin_.extend(data)
    g['bufferViews'].append({'buffer': 0, 'byteOffset': off, 'byteLength': len(data)})
    a = {'bufferView': len(g['bufferViews']) - 1, 'componentType': 5126, 'count': count, 'type': typ}
    if mn is not None: a['min'], a['max'] = mn, mx
    g['accessors'].append(a); return len(g['accessors']) - 1
ti = add(struct.pack('<%df' % keys, *times), 'SCALAR', keys, [times[0]], [times[-1]])
vi = add(struct.pack('<%df' % (3 * keys), *vals), 'VEC3', keys)
node = next(i for i, nd in enumerate(g['nodes']) if nd.get('name') == joint_name)
walk['samplers'].append({'input': ti, 'output': vi, 'interpolation': 'LINEAR'})
walk['channels'].append({'sampler': len(walk['samplers']) - 1, 'target': {'node': node, 'path': 'scale'}})
g['buffers'][0]['byteLength'] = len(bin_)
js = json.dumps(g).encode()
while len(js) % 4: js += b' '
out_b = struct.pack('<III', 0x46546C67, 2, 12 + 8 + len(js) + 8 + len(bin_)) + struct.pack('<II', len(js), 0x4E4F534A) + js + struct.pack('<II', len(bin_), 0x004E4942) + bin_
open(out, 'wb').write(out_b)
print('joint', joint_name, 'node', node)
