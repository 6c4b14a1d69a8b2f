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

usage: gltf_variants.py IN.glb OUT_DIR   (writes OUT_DIR/<stem>_<variant>.glb for each variant that
                                          applies: root_motion needs an animation)
"""
import copy
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


VARIANTS = [zup, cm, matrices, no_ibm, root_motion, skeleton, loose_weights]


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


if __name__ == '__main__':
    main()
