#!/usr/bin/env python3
"""Valid variants of one .glb character, each written the way some exporter writes a file, for the
three.js cross-check (threejs_crosscheck.sh): the same character, posed the same by any reader
that follows the specification, but reached through what the original file does not use.

  zup          the scene under a root node turned -90 degrees about x and moved (a Z-up tool's
               export: the armature is not at the scene's origin)
  cm           the scene under a root node scaled 100 (centimetres)
  matrices     every node no animation drives stored as a matrix, not TRS
  no_ibm       skins without inverseBindMatrices (identity by the specification)
  root_motion  the scene under a node that the first animation moves (root motion on a node
               that is not a joint)
  skeleton     each skin names its first joint as its skeleton root
  loose_weights  float weights summing to 0.5, not 1 (readers normalize them; the validator
               reports them, exporters that skip normalizing write them)
  interleaved  each primitive's attributes interleaved in one strided buffer view
  non_indexed  triangles without indices, every corner its own vertex
  strips       each primitive one triangle strip (mode 5), joined by degenerate triangles
  byte_weights the four largest influences, weights as normalized bytes, joints as shorts
  cubic        linear keys as CUBICSPLINE with zero tangents
  sparse       POSITION with every seventh vertex held in a sparse block
  zero_scale   a joint scaled to zero over the middle third of a clip (a part hidden)
  embedded     (.gltf) the buffer as a base64 data: URI
  spaced       (.gltf) the buffer in "<stem> model.bin", its URI percent-encoded

usage: gltf_variants.py IN.glb OUT_DIR   (writes OUT_DIR/<stem>_<variant>.glb, or .gltf, for each
                                          variant that applies: root_motion needs an animation,
                                          zero_scale a joint's scale channel)
"""
import base64
import copy
import json
import math
import os
import struct
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', 'robustness'))
from campaign import glb_bytes, read_glb  # noqa: E402 (the campaign's GLB reader and writer)


def under_new_root(doc, node):
    """Puts the default scene's root nodes under `node`, a new node; returns its index."""
    doc['nodes'].append(node)
    index = len(doc['nodes']) - 1
    scene = doc['scenes'][doc.get('scene', 0)]
    node['children'], scene['nodes'] = scene['nodes'], [index]
    return index


def add_accessor(doc, binary, data, count, kind):
    binary.extend(b'\0' * (-len(binary) % 4))
    doc['bufferViews'].append({'buffer': 0, 'byteOffset': len(binary), 'byteLength': len(data)})
    binary.extend(data)
    doc['buffers'][0]['byteLength'] = len(binary)
    doc['accessors'].append({'bufferView': len(doc['bufferViews']) - 1, 'componentType': 5126,
                             'count': count, 'type': kind})
    return len(doc['accessors']) - 1


def zup(doc, binary):
    under_new_root(doc, {'name': 'zup', 'rotation': [-math.sqrt(0.5), 0, 0, math.sqrt(0.5)],
                         'translation': [1, 2, 3]})


def cm(doc, binary):
    under_new_root(doc, {'name': 'cm', 'scale': [100, 100, 100]})


def matrices(doc, binary):
    driven = {c['target'].get('node') for a in doc.get('animations', []) for c in a['channels']}
    for i, node in enumerate(doc['nodes']):
        if i in driven or 'matrix' in node:
            continue
        t = node.pop('translation', [0, 0, 0])
        x, y, z, w = node.pop('rotation', [0, 0, 0, 1])
        s = node.pop('scale', [1, 1, 1])
        rows = [[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]]
        columns = [[rows[r][c] * s[c] for r in range(3)] + [0] for c in range(3)]
        node['matrix'] = columns[0] + columns[1] + columns[2] + t + [1]


def no_ibm(doc, binary):
    for skin in doc.get('skins', []):
        skin.pop('inverseBindMatrices', None)


def root_motion(doc, binary):
    if not doc.get('animations'):
        return False  # nothing to add root motion to
    mover = under_new_root(doc, {'name': 'mover'})
    animation = doc['animations'][0]
    times = animation['samplers'][0]['input']
    n = doc['accessors'][times]['count']
    path = b''.join(struct.pack('<3f', 0.5 * i / max(n - 1, 1), 0.1 * math.sin(i), 0)
                    for i in range(n))
    animation['samplers'].append({'input': times,
                                  'output': add_accessor(doc, binary, path, n, 'VEC3')})
    animation['channels'].append({'sampler': len(animation['samplers']) - 1,
                                  'target': {'node': mover, 'path': 'translation'}})


def skeleton(doc, binary):
    for skin in doc.get('skins', []):
        skin['skeleton'] = skin['joints'][0]


def loose_weights(doc, binary):
    done = set()
    for mesh in doc['meshes']:
        for primitive in mesh['primitives']:
            for name, index in primitive['attributes'].items():
                accessor = doc['accessors'][index]
                if not name.startswith('WEIGHTS_') or index in done or \
                        accessor['componentType'] != 5126:
                    continue
                done.add(index)
                view = doc['bufferViews'][accessor['bufferView']]
                stride = view.get('byteStride', 16)
                base = view.get('byteOffset', 0) + accessor.get('byteOffset', 0)
                for i in range(accessor['count']):
                    for c in range(4):
                        at = base + i * stride + 4 * c
                        struct.pack_into('<f', binary, at,
                                         0.5 * struct.unpack_from('<f', binary, at)[0])
                accessor.pop('min', None)
                accessor.pop('max', None)


SIZES = {5120: 1, 5121: 1, 5122: 2, 5123: 2, 5125: 4, 5126: 4}
WIDTHS = {'SCALAR': 1, 'VEC2': 2, 'VEC3': 3, 'VEC4': 4, 'MAT4': 16}


def elements(doc, binary, index):
    """The accessor's elements as raw bytes, one entry each (no sparse accessors)."""
    accessor = doc['accessors'][index]
    size = SIZES[accessor['componentType']] * WIDTHS[accessor['type']]
    view = doc['bufferViews'][accessor['bufferView']]
    stride = view.get('byteStride', size)
    base = view.get('byteOffset', 0) + accessor.get('byteOffset', 0)
    return [bytes(binary[base + i * stride:base + i * stride + size])
            for i in range(accessor['count'])]


def packed_like(doc, binary, index, data):
    """A new tightly packed accessor of `index`'s kind holding the elements `data`."""
    old = doc['accessors'][index]
    new = add_accessor(doc, binary, b''.join(data), len(data), old['type'])
    accessor = doc['accessors'][new]
    accessor['componentType'] = old['componentType']
    for key in ('normalized', 'min', 'max'):
        if key in old:
            accessor[key] = old[key]
    return new


def primitives(doc):
    return [p for mesh in doc['meshes'] for p in mesh['primitives']]


def interleaved(doc, binary):
    for primitive in primitives(doc):
        names = sorted(primitive['attributes'])
        columns = [[e + b'\0' * (-len(e) % 4) for e in  # each element 4-byte aligned
                    elements(doc, binary, primitive['attributes'][n])] for n in names]
        stride = sum(len(c[0]) for c in columns)
        binary.extend(b'\0' * (-len(binary) % 4))
        data = b''.join(b''.join(c[i] for c in columns) for i in range(len(columns[0])))
        doc['bufferViews'].append({'buffer': 0, 'byteOffset': len(binary),
                                   'byteLength': len(data), 'byteStride': stride,
                                   'target': 34962})
        binary.extend(data)
        doc['buffers'][0]['byteLength'] = len(binary)
        offset = 0
        for name, column in zip(names, columns):
            accessor = dict(doc['accessors'][primitive['attributes'][name]])
            accessor.update(bufferView=len(doc['bufferViews']) - 1, byteOffset=offset)
            doc['accessors'].append(accessor)
            primitive['attributes'][name] = len(doc['accessors']) - 1
            offset += len(column[0])


def corners(doc, binary, primitive):
    if 'indices' not in primitive:
        return list(range(doc['accessors'][primitive['attributes']['POSITION']]['count']))
    return [struct.unpack('<' + {1: 'B', 2: 'H', 4: 'I'}[len(e)], e)[0]
            for e in elements(doc, binary, primitive['indices'])]


def non_indexed(doc, binary):
    for primitive in primitives(doc):
        if 'indices' not in primitive:
            continue
        order = corners(doc, binary, primitive)
        for sets in [primitive['attributes']] + primitive.get('targets', []):
            for name, index in sets.items():
                column = elements(doc, binary, index)
                sets[name] = packed_like(doc, binary, index, [column[i] for i in order])
        del primitive['indices']


def strips(doc, binary):
    """Each triangle list as one strip, triangles joined by degenerate ones, each starting at an
    even position so that it keeps its winding."""
    for primitive in primitives(doc):
        order = corners(doc, binary, primitive)
        strip = []
        for t in range(0, len(order), 3):
            if strip:
                strip += [strip[-1], order[t]]
                if len(strip) % 2:
                    strip.append(order[t])
            strip += order[t:t + 3]
        primitive['indices'] = add_accessor(doc, binary, struct.pack(f'<{len(strip)}I', *strip),
                                            len(strip), 'SCALAR')
        doc['accessors'][primitive['indices']]['componentType'] = 5125
        primitive['mode'] = 5


def byte_weights(doc, binary):
    """Skins as tools limited to four influences quantize them (gltfpack, many engines' exporters):
    the four largest influences, weights as normalized unsigned bytes summing to 255, joints as
    unsigned shorts (0 where the weight is)."""
    for primitive in primitives(doc):
        attributes = primitive['attributes']
        sets = sorted(n[len('WEIGHTS_'):] for n in attributes if n.startswith('WEIGHTS_'))
        if not sets or any(doc['accessors'][attributes['WEIGHTS_' + k]]['componentType'] != 5126
                           for k in sets):
            continue
        columns = [(elements(doc, binary, attributes['JOINTS_' + k]),
                    elements(doc, binary, attributes['WEIGHTS_' + k]), k) for k in sets]
        joints, weights = [], []
        for v in range(len(columns[0][0])):
            pairs = []
            for j, w, k in columns:
                kind = '<4' + ('B' if len(j[v]) == 4 else 'H')
                pairs += zip(struct.unpack('<4f', w[v]), struct.unpack(kind, j[v]))
            pairs = sorted(pairs, key=lambda p: (-p[0], p[1]))[:4]
            total = sum(w for w, _ in pairs) or 1
            q = [round(255 * w / total) for w, _ in pairs]
            q[0] += 255 - sum(q)  # sums to 255 exactly
            weights.append(bytes(q))
            joints.append(struct.pack('<4H', *[j if w else 0 for (_, j), w in zip(pairs, q)]))
        for k in sets:
            if k != '0':
                del attributes['JOINTS_' + k], attributes['WEIGHTS_' + k]
        attributes['JOINTS_0'] = packed_like(doc, binary, attributes['JOINTS_0'], joints)
        doc['accessors'][attributes['JOINTS_0']]['componentType'] = 5123
        attributes['WEIGHTS_0'] = packed_like(doc, binary, attributes['WEIGHTS_0'], weights)
        doc['accessors'][attributes['WEIGHTS_0']].update(componentType=5121, normalized=True)


def cubic(doc, binary):
    """Linear samplers as CUBICSPLINE with zero tangents (an ease between keys)."""
    for animation in doc.get('animations', []):
        for sampler in animation['samplers']:
            if sampler.get('interpolation', 'LINEAR') != 'LINEAR':
                continue
            values = elements(doc, binary, sampler['output'])
            zero = b'\0' * len(values[0])
            sampler['output'] = packed_like(doc, binary, sampler['output'],
                                            [x for v in values for x in (zero, v, zero)])
            doc['accessors'][sampler['output']].pop('min', None)
            doc['accessors'][sampler['output']].pop('max', None)
            sampler['interpolation'] = 'CUBICSPLINE'


def sparse(doc, binary):
    """Each float POSITION as a view with every seventh vertex at the origin and a sparse block
    restoring them (a reader that skips sparse blocks draws a different mesh)."""
    for primitive in primitives(doc):
        index = primitive['attributes']['POSITION']
        old = doc['accessors'][index]
        if old['componentType'] != 5126 or 'sparse' in old:
            continue  # quantized positions (gltfpack's): kept as they are
        points = elements(doc, binary, index)
        moved = list(range(0, len(points), 7))
        base = [b'\0' * 12 if i % 7 == 0 else e for i, e in enumerate(points)]
        accessor = doc['accessors'][packed_like(doc, binary, index, base)]
        at = add_accessor(doc, binary, struct.pack(f'<{len(moved)}I', *moved), len(moved), 'SCALAR')
        where = doc['accessors'].pop(at)['bufferView']
        at = add_accessor(doc, binary, b''.join(points[i] for i in moved), len(moved), 'VEC3')
        what = doc['accessors'].pop(at)['bufferView']
        accessor['sparse'] = {'count': len(moved),
                              'indices': {'bufferView': where, 'componentType': 5125},
                              'values': {'bufferView': what}}
        primitive['attributes']['POSITION'] = len(doc['accessors']) - 1


def zero_scale(doc, binary):
    """A joint scaled to zero over the middle third of its keys (as games hide a part): the first
    animation's first scale channel on a skin's joint."""
    joints = {j for skin in doc.get('skins', []) for j in skin['joints']}
    for animation in doc.get('animations', [])[:1]:
        for channel in animation['channels']:
            if channel['target']['path'] != 'scale' or channel['target'].get('node') not in joints:
                continue
            sampler = animation['samplers'][channel['sampler']]
            values = elements(doc, binary, sampler['output'])
            per = 3 if sampler.get('interpolation') == 'CUBICSPLINE' else 1
            keys = len(values) // per
            zeroed = [b'\0' * 12 if keys // 3 <= i // per < 2 * keys // 3 else v
                      for i, v in enumerate(values)]
            sampler['output'] = packed_like(doc, binary, sampler['output'], zeroed)
            doc['accessors'][sampler['output']].pop('min', None)
            doc['accessors'][sampler['output']].pop('max', None)
            return None
    return False  # no joint's scale is animated


VARIANTS = [zup, cm, matrices, no_ibm, root_motion, skeleton, loose_weights, interleaved,
            non_indexed, strips, byte_weights, cubic, sparse, zero_scale]


def main():
    source, out = sys.argv[1], sys.argv[2]
    stem = os.path.splitext(os.path.basename(source))[0]
    doc, binary = read_glb(source)
    for variant in VARIANTS:
        d, b = copy.deepcopy(doc), bytearray(binary)
        if variant(d, b) is False:
            continue
        with open(os.path.join(out, f'{stem}_{variant.__name__}.glb'), 'wb') as f:
            f.write(glb_bytes(d, b))
    # The same file as .gltf text: its buffer embedded, or beside it under a name with a space.
    for variant, uri in [('embedded', 'data:application/octet-stream;base64,' +
                          base64.b64encode(binary).decode()),
                         ('spaced', f'{stem}%20model.bin')]:
        d = copy.deepcopy(doc)
        d['buffers'][0]['uri'] = uri
        if variant == 'spaced':
            with open(os.path.join(out, f'{stem} model.bin'), 'wb') as f:
                f.write(binary)
        with open(os.path.join(out, f'{stem}_{variant}.gltf'), 'w') as f:
            json.dump(d, f)


if __name__ == '__main__':
    main()
