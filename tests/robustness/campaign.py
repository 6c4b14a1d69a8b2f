#!/usr/bin/env python3
"""The malformed-input campaign: mutates real characters into a few hundred broken glTF files (and
a cloth cache into damaged PC2 files) and runs each through the commands that read it (a glTF
through anim, lod, impostor, outfits, terrain and as the outfit of its unbroken body; a cache
through cloth), classifying each run:

  handled   exit 1 (or 2) with one "crowdbake: error:" / "crowdbake: usage:" line on stderr
  accepted  exit 0: the mutation is harmless to the bake; every such case must be listed, with
            the reason, in accepted.txt beside this script (and nothing else may be listed)
  crash     a signal, a sanitizer report, any other exit code or stderr
  hang      stopped by its own --max-seconds guard (GUARD), or still running HANG_MARGIN seconds
            after it (the guard failed)
  memory    peak resident memory over --max-rss MiB (or stopped by the --max-memory guard)
  bad pack  exit 0, but `crowdbake verify` rejects the pack written

Exit 0 when there is no crash, hang, memory or bad-pack case and the accepted cases match accepted.txt.

usage: campaign.py BIN_DIR WORK_DIR [--assets DIR] [--jobs N] [--max-rss MIB]
                   [--table FILE.md] [--rotate | --one] [--every N] [--only REGEX]
"""
import argparse
import base64
import concurrent.futures
import copy
import json
import os
import re
import shutil
import signal
import struct
import subprocess
import sys
import threading
import time
import zlib

HERE = os.path.dirname(os.path.abspath(__file__))


# --- glTF files ----------------------------------------------------------------------------

def read_glb(path):
    data = open(path, 'rb').read()
    json_len = struct.unpack_from('<I', data, 12)[0]
    doc = json.loads(data[20:20 + json_len])
    rest = data[20 + json_len:]
    binary = rest[8:8 + struct.unpack_from('<I', rest, 0)[0]] if len(rest) >= 8 else b''
    return doc, bytearray(binary)


def glb_bytes(doc, binary, text=None):
    text = (text if text is not None else json.dumps(doc, separators=(',', ':'))).encode()
    text += b' ' * (-len(text) % 4)
    binary = bytes(binary) + b'\0' * (-len(binary) % 4)
    out = struct.pack('<4sII', b'glTF', 2, 12 + 8 + len(text) + (8 + len(binary) if binary else 0))
    out += struct.pack('<I4s', len(text), b'JSON') + text
    if binary:
        out += struct.pack('<I4s', len(binary), b'BIN\0') + binary
    return out


def accessor_offset(doc, index):
    acc = doc['accessors'][index]
    view = doc['bufferViews'][acc['bufferView']]
    return view.get('byteOffset', 0) + acc.get('byteOffset', 0)


def set_path(doc, path, value):
    """Sets doc[path...] (adding the last key where its parent exists) or, with DELETE, removes it."""
    node = doc
    for key in path[:-1]:
        node = node[key]
    if value is DELETE:
        del node[path[-1]]
    else:
        node[path[-1]] = value


def has_path(doc, path):
    node = doc
    for key in path:
        try:
            node = node[key]
        except (KeyError, IndexError, TypeError):
            return False
    return True


DELETE = object()


# --- the cases -------------------------------------------------------------------------------

class Case:
    def __init__(self, name, write, base, kind='gltf'):
        # write(folder) -> input path; base: the unbroken input it was made from; kind: 'gltf'
        # (a character or environment) or 'cache' (a cloth cache)
        self.name, self.write, self.base, self.kind = name, write, base, kind


def glb_case(name, base, mutate):
    def write(folder):
        doc, binary = read_glb(base)
        result = mutate(doc, binary)
        path = os.path.join(folder, name + '.glb')
        open(path, 'wb').write(result if isinstance(result, (bytes, bytearray)) else
                               glb_bytes(doc, binary))
        return path
    return Case(name, write, base)


def gltf_case(name, base_dir, base_name, mutate):
    """A .gltf with external files: the base folder is copied, then mutate(doc, folder)."""
    def write(folder):
        shutil.copytree(base_dir, folder, dirs_exist_ok=True)
        doc = json.load(open(os.path.join(base_dir, base_name)))
        text = mutate(doc, folder)
        path = os.path.join(folder, name + '.gltf')
        open(path, 'w').write(text if isinstance(text, str) else json.dumps(doc))
        return path
    return Case(name, write, os.path.join(base_dir, base_name))


def build_cases(assets, samples):
    cases = []
    rigged = os.path.join(assets, 'RiggedSimple/RiggedSimple.glb')
    quad = os.path.join(assets, 'quad_skin/quad_skin.glb')
    fox = os.path.join(assets, 'Fox/Fox.glb')
    simple = os.path.join(assets, 'SimpleSkin')
    glbs = [('rigged', rigged), ('quad', quad), ('fox', fox)]

    # Truncations and header lies.
    for tag, base in glbs:
        size = os.path.getsize(base)
        for frac in (0, 0.002, 0.01, 0.05, 0.2, 0.5, 0.8, 0.95, 0.999):
            cut = int(size * frac)
            cases.append(glb_case(f'{tag}_truncated_{cut}', base,
                                  lambda d, b, base=base, cut=cut: open(base, 'rb').read()[:cut]))

        def lie(offset, value, fmt='<I', base=base):
            def m(d, b):
                data = bytearray(open(base, 'rb').read())
                struct.pack_into(fmt, data, offset, value)
                return data
            return m
        json_len = struct.unpack_from('<I', open(base, 'rb').read(), 12)[0]
        bin_at = 20 + json_len
        for what, off, value in [('magic', 0, 0x58546c67), ('version1', 4, 1), ('version3', 4, 3),
                                 ('length_short', 8, 20), ('length_long', 8, size + 4096),
                                 ('json_length_huge', 12, 0xfffffff0), ('json_length_zero', 12, 0),
                                 ('json_type', 16, 0x4e4f534b), ('bin_length_huge', bin_at, 0xfffffff0),
                                 ('bin_type', bin_at + 4, 0x4e4f534a)]:
            cases.append(glb_case(f'{tag}_header_{what}', base, lie(off, value)))

    # Field mutations: each reference and count a bake follows, set to what lies.
    targets = [
        ('acc0_count', ['accessors', 0, 'count']), ('acc0_ctype', ['accessors', 0, 'componentType']),
        ('acc0_type', ['accessors', 0, 'type']), ('acc0_view', ['accessors', 0, 'bufferView']),
        ('acc0_offset', ['accessors', 0, 'byteOffset']), ('acc1_count', ['accessors', 1, 'count']),
        ('view0_length', ['bufferViews', 0, 'byteLength']), ('view0_offset', ['bufferViews', 0, 'byteOffset']),
        ('view1_stride', ['bufferViews', 1, 'byteStride']), ('view0_buffer', ['bufferViews', 0, 'buffer']),
        ('buffer0_length', ['buffers', 0, 'byteLength']),
        ('prim_indices', ['meshes', 0, 'primitives', 0, 'indices']),
        ('prim_position', ['meshes', 0, 'primitives', 0, 'attributes', 'POSITION']),
        ('prim_joints', ['meshes', 0, 'primitives', 0, 'attributes', 'JOINTS_0']),
        ('prim_weights', ['meshes', 0, 'primitives', 0, 'attributes', 'WEIGHTS_0']),
        ('prim_mode', ['meshes', 0, 'primitives', 0, 'mode']),
        ('prim_material', ['meshes', 0, 'primitives', 0, 'material']),
        ('node_mesh', ['nodes', 0, 'mesh']), ('node_children', ['nodes', 0, 'children']),
        ('skin_joints', ['skins', 0, 'joints']), ('skin_ibm', ['skins', 0, 'inverseBindMatrices']),
        ('sampler_input', ['animations', 0, 'samplers', 0, 'input']),
        ('sampler_output', ['animations', 0, 'samplers', 0, 'output']),
        ('sampler_interp', ['animations', 0, 'samplers', 0, 'interpolation']),
        ('channel_node', ['animations', 0, 'channels', 0, 'target', 'node']),
        ('channel_path', ['animations', 0, 'channels', 0, 'target', 'path']),
        ('scene', ['scene']), ('scene_nodes', ['scenes', 0, 'nodes']),
    ]
    values = [('neg', -1), ('huge', 2147483647), ('string', 'x'), ('null', None), ('gone', DELETE)]
    for tag, base in [('rigged', rigged)]:
        doc = read_glb(base)[0]
        for tname, path in targets:
            for vname, value in values:
                if not has_path(doc, path[:-1]) or value is DELETE and not has_path(doc, path):
                    continue  # the mutation would change nothing
                def m(d, b, path=path, value=value):
                    set_path(d, path, value if value is DELETE else copy.deepcopy(value))
                cases.append(glb_case(f'{tag}_{tname}_{vname}', base, m))
    for tname, path in [('image_view', ['images', 0, 'bufferView']), ('texture_source', ['textures', 0, 'source']),
                        ('image_mime', ['images', 0, 'mimeType']),
                        ('material_texture', ['materials', 0, 'pbrMetallicRoughness', 'baseColorTexture', 'index'])]:
        for vname, value in values:
            if value is DELETE and not has_path(read_glb(fox)[0], path):
                continue
            cases.append(glb_case(f'fox_{tname}_{vname}', fox,
                                  lambda d, b, path=path, value=value: set_path(d, path, value if value is DELETE else copy.deepcopy(value))))

    # Counts that claim more than the file holds, and work that grows from counts.
    def rigged_with(fn):
        return lambda d, b: fn(d, b)
    for name, fn in [
        ('count_2p28_position', lambda d, b: d['accessors'][d['meshes'][0]['primitives'][0]['attributes']['POSITION']].update(count=1 << 28)),
        ('count_2p32_indices', lambda d, b: d['accessors'][0].update(count=1 << 32)),
        ('count_2p28_ibm', lambda d, b: d['accessors'][d['skins'][0]['inverseBindMatrices']].update(count=1 << 28)),
        ('count_2p28_times', lambda d, b: d['accessors'][d['animations'][0]['samplers'][0]['input']].update(count=1 << 28)),
        ('view_length_2p31', lambda d, b: d['bufferViews'][0].update(byteLength=1 << 31)),
        ('stride_1', lambda d, b: d['bufferViews'][1].update(byteStride=1)),
        ('joints_70000', lambda d, b: d['skins'][0].update(joints=list(range(70000)))),
        ('primitives_300_shared', lambda d, b: d['meshes'][0].update(primitives=d['meshes'][0]['primitives'] * 300)),
        ('primitives_20000_shared', lambda d, b: d['meshes'][0].update(primitives=d['meshes'][0]['primitives'] * 20000)),
        ('nodes_20000_same_mesh', lambda d, b: (d['nodes'].extend({'mesh': 0} for _ in range(20000)),
                                                d['scenes'][0]['nodes'].extend(range(len(d['nodes']) - 20000, len(d['nodes']))))),
        ('accessor_no_view_2p24', lambda d, b: d['accessors'][d['meshes'][0]['primitives'][0]['attributes']['POSITION']].update(count=1 << 24) or
         d['accessors'][d['meshes'][0]['primitives'][0]['attributes']['POSITION']].pop('bufferView')),
    ]:
        cases.append(glb_case(f'rigged_{name}', rigged, rigged_with(fn)))

    def poke_float(accessor_of, index, value):
        def m(d, b):
            struct.pack_into('<f', b, accessor_offset(d, accessor_of(d)) + 4 * index, value)
        return m
    pos = lambda d: d['meshes'][0]['primitives'][0]['attributes']['POSITION']
    wts = lambda d: d['meshes'][0]['primitives'][0]['attributes']['WEIGHTS_0']
    ibm = lambda d: d['skins'][0]['inverseBindMatrices']
    times = lambda d: d['animations'][0]['samplers'][0]['input']
    outs = lambda d: d['animations'][0]['samplers'][0]['output']
    for name, acc, index, value in [('nan_position', pos, 1, float('nan')), ('inf_position', pos, 0, float('inf')),
                                    ('nan_ibm', ibm, 5, float('nan')), ('nan_time', times, 1, float('nan')),
                                    ('nan_output', outs, 2, float('nan')), ('huge_position', pos, 2, 3e38),
                                    ('time_backwards', times, 1, -5.0)]:
        cases.append(glb_case(f'rigged_{name}', rigged, poke_float(acc, index, value)))
    if wts(read_glb(rigged)[0]) is not None:
        doc, _ = read_glb(rigged)
        if doc['accessors'][wts(doc)]['componentType'] == 5126:
            cases.append(glb_case('rigged_nan_weight', rigged, poke_float(wts, 0, float('nan'))))
            cases.append(glb_case('rigged_negative_weight', rigged, poke_float(wts, 0, -1.0)))

    def long_clip(d, b):  # key times stretched into a 3,333 s clip
        acc = d['accessors'][times(d)]
        at = accessor_offset(d, times(d))
        scale = 3333 / acc['max'][0]
        for i in range(acc['count']):
            (t,) = struct.unpack_from('<f', b, at + 4 * i)
            struct.pack_into('<f', b, at + 4 * i, t * scale)
        acc['max'] = [3333.0]
    cases.append(glb_case('rigged_clip_3333s', rigged, long_clip))

    # Cycles and broken graphs.
    for name, fn in [
        ('self_child', lambda d, b: d['nodes'][0].update(children=[0])),
        ('two_cycle', lambda d, b: (d['nodes'][0].setdefault('children', []).append(1), d['nodes'][1].setdefault('children', []).append(0))),
        ('two_parents', lambda d, b: d['nodes'][2].setdefault('children', []).append(d['nodes'][0].get('children', [1])[0])),
        ('joint_twice', lambda d, b: d['skins'][0]['joints'].append(d['skins'][0]['joints'][0])),
        ('skeleton_missing', lambda d, b: d['skins'][0].update(skeleton=999)),
        ('child_missing', lambda d, b: d['nodes'][0].update(children=[999])),
    ]:
        cases.append(glb_case(f'rigged_{name}', rigged, fn))

    # URIs of a .gltf with external buffers.
    def uri(value, prep=None):
        def m(doc, folder):
            if prep:
                prep(folder)
            doc['buffers'][0]['uri'] = value
        return m
    outside = lambda folder: shutil.copy(os.path.join(folder, 'skinGeometry.bin'), os.path.join(folder, '..', 'outside.bin'))
    def link(target):
        return lambda folder: os.symlink(target, os.path.join(folder, 'link.bin'))
    for name, m in [
        ('uri_traversal', uri('../outside.bin', outside)), ('uri_traversal_percent', uri('%2E%2E/outside.bin', outside)),
        ('uri_traversal_inner', uri('sub/../../outside.bin', outside)), ('uri_absolute', uri('/etc/hostname')),
        ('uri_dev_zero', uri('/dev/zero')), ('uri_dev_zero_relative', uri('../../../../../../../../dev/zero')),
        ('uri_link_out', uri('link.bin', lambda f: (outside(f), link('../outside.bin')(f)))),
        ('uri_link_dev_zero', uri('link.bin', link('/dev/zero'))),
        ('uri_link_inside', uri('link.bin', link('skinGeometry.bin'))),
        ('uri_directory', uri('sub', lambda f: os.mkdir(os.path.join(f, 'sub')))),
        ('uri_fifo', uri('fifo.bin', lambda f: os.mkfifo(os.path.join(f, 'fifo.bin')))),
        ('uri_missing', uri('missing.bin')), ('uri_empty', uri('')),
        ('uri_bad_data', uri('data:application/octet-stream;base64,@@@@')),
        ('uri_data_short', uri('data:application/octet-stream;base64,' + base64.b64encode(b'\0' * 16).decode())),
        ('uri_long', uri('a' * 5000 + '.bin')), ('uri_nul', uri('skinGeometry.bin\u0000.x')),
    ]:
        cases.append(gltf_case(f'simple_{name}', simple, 'SimpleSkin.gltf', m))

    # Nesting.
    deep = lambda n: '{"a":' * n + '1' + '}' * n
    def nested(n):
        def m(doc, folder):
            text = json.dumps(doc)
            return text[:-1] + ', "extras": ' + deep(n) + '}'
        return m
    for n in (60, 65, 100000):
        cases.append(gltf_case(f'simple_nesting_{n}', simple, 'SimpleSkin.gltf', nested(n)))
    cases.append(glb_case('rigged_nesting_100000', rigged,
                          lambda d, b: glb_bytes(d, b, json.dumps(d)[:-1] + ', "extras": ' + deep(100000) + '}')))
    cases.append(glb_case('rigged_nesting_arrays_100000', rigged,
                          lambda d, b: glb_bytes(d, b, json.dumps(d)[:-1] + ', "extras": ' + '[' * 100000 + ']' * 100000 + '}')))

    # Images a bake decodes: the Fox's PNG replaced by one that lies in its header, is corrupt,
    # cut or no image, in the GLB's binary chunk and as a data URI.
    def png(width, height, idat):
        chunk = lambda kind, data: (struct.pack('>I', len(data)) + kind + data +
                                    struct.pack('>I', zlib.crc32(kind + data)))
        return (b'\x89PNG\r\n\x1a\n' + chunk(b'IHDR', struct.pack('>IIBBBBB', width, height, 8, 6, 0, 0, 0)) +
                chunk(b'IDAT', idat) + chunk(b'IEND', b''))
    def corrupt_zlib(real):  # the first IDAT's data inverted, its CRC made right again
        at = real.index(b'IDAT') - 4
        length = struct.unpack_from('>I', real, at)[0]
        data = bytes(x ^ 0xff for x in real[at + 8:at + 8 + length])
        return (real[:at + 8] + data + struct.pack('>I', zlib.crc32(b'IDAT' + data)) +
                real[at + 12 + length:])
    images = [('60000x60000', lambda real: png(60000, 60000, zlib.compress(b'\0' * 4096))),
              ('1x2p30', lambda real: png(1, 1 << 30, zlib.compress(b'\0' * 4096))),
              ('corrupt_zlib', corrupt_zlib), ('truncated', lambda real: real[:len(real) // 2]),
              ('not_png', lambda real: b'this is not an image\n' * 8), ('empty', lambda real: b'')]
    def replace_image(damage, as_uri):
        def m(d, b):
            image = d['images'][0]
            view = d['bufferViews'][image['bufferView']]
            at = view.get('byteOffset', 0)
            bad = damage(bytes(b[at:at + view['byteLength']]))
            if as_uri:
                del image['bufferView']
                image['uri'] = 'data:image/png;base64,' + base64.b64encode(bad).decode()
                return
            b.extend(b'\0' * (-len(b) % 4))
            d['bufferViews'].append({'buffer': 0, 'byteOffset': len(b), 'byteLength': len(bad)})
            b.extend(bad)
            image['bufferView'] = len(d['bufferViews']) - 1
            d['buffers'][0]['byteLength'] = len(b)
        return m
    for iname, damage in images:
        cases.append(glb_case(f'fox_image_{iname}', fox, replace_image(damage, False)))
        cases.append(glb_case(f'fox_image_{iname}_uri', fox, replace_image(damage, True)))
    return cases


# --- damaged cloth caches ------------------------------------------------------------------------

# The garment the caches drape: the fuzzers' quad (one joint, clip "wave" of 1 s), posed by
# `crowdbake pose` over 8 cycles at 8 fps into the PC2 every case damages.
QUAD = os.path.join(HERE, '../fuzz/seed_quad.gltf')


def good_cache(bin_dir, work):
    b = os.path.join(bin_dir, 'crowdbake')
    pack, cache = os.path.join(work, 'quad.crowdpack'), os.path.join(work, 'quad_cycles.pc2')
    subprocess.run([b, 'anim', QUAD, '-o', pack, '--quiet'], check=True)
    times = ','.join(str(i / 8) for i in range(65))
    subprocess.run([b, 'pose', pack, '--clip', 'wave', '-o', cache, '--times', times, '--quiet'],
                   check=True)
    return cache


def cache_cases(base):
    """PC2: 'POINTCACHE2\\0', int32 version, int32 points, float start, float rate, int32 samples,
    then samples x points x 3 floats."""
    good = open(base, 'rb').read()
    points, samples = struct.unpack_from('<i', good, 16)[0], struct.unpack_from('<i', good, 28)[0]
    def case(name, damage):
        def write(folder):
            path = os.path.join(folder, name + '.pc2')
            open(path, 'wb').write(damage(bytearray(good)))
            return path
        return Case(f'cache_{name}', write, base, 'cache')
    def field(offset, fmt, value):
        return lambda d: (struct.pack_into(fmt, d, offset, value), d)[1]
    vertex = lambda frame, point: 32 + 12 * (frame * points + point)
    cases = [case(f'truncated_{cut}', lambda d, cut=cut: d[:cut])
             for cut in (0, 5, 11, 12, 20, 31, 32, 32 + 12 * points - 4, len(good) // 2, len(good) - 1)]
    for name, offset, fmt, value in [
            ('magic', 0, '<12s', b'POINTCACHE3\0'), ('version_2', 12, '<i', 2),
            ('points_zero', 16, '<i', 0), ('points_negative', 16, '<i', -1),
            ('points_huge', 16, '<i', 2147483647), ('points_one_more', 16, '<i', points + 1),
            ('start_nan', 20, '<f', float('nan')), ('start_inf', 20, '<f', float('inf')),
            ('start_huge', 20, '<f', -1e30), ('rate_zero', 24, '<f', 0.0),
            ('rate_negative', 24, '<f', -1.0), ('rate_nan', 24, '<f', float('nan')),
            ('rate_inf', 24, '<f', float('inf')), ('samples_zero', 28, '<i', 0),
            ('samples_negative', 28, '<i', -1), ('samples_huge', 28, '<i', 2147483647),
            ('samples_one_more', 28, '<i', samples + 1),
            ('z_nan', vertex(samples // 2, 0) + 8, '<f', float('nan')),
            ('z_inf', vertex(1, points - 1) + 8, '<f', float('inf')),
            ('z_huge', vertex(2, 0) + 8, '<f', 3e38)]:
        cases.append(case(name, field(offset, fmt, value)))
    cases.append(case('trailing_bytes', lambda d: d + b'\0' * 7))
    cases.append(case('one_sample', lambda d: (struct.pack_into('<i', d, 28, 1), d[:32 + 12 * points])[1]))
    return cases


# --- running ---------------------------------------------------------------------------------

# Every bake stops itself past GUARD seconds (its --max-seconds); a run still going HANG_MARGIN
# seconds after that is a hang: its own guard failed, whatever this machine's speed.
GUARD, HANG_MARGIN = 120, 60
GLTF_COMMANDS = ('anim', 'lod', 'impostor', 'outfits', 'terrain', 'outfit')


def commands(bin_dir, case, path, out):
    b = os.path.join(bin_dir, 'crowdbake')
    guard = ['--max-seconds', str(GUARD), '--quiet']
    if case.kind == 'cache':
        return {'cloth': [b, 'cloth', path, '--body', QUAD, '--outfit', 'quad=' + QUAD, '--garment',
                          'skin', '--clip', 'wave', '--fps', '8', '-o', out + '.cloth.crowdpack'] + guard}
    return {
        'anim': [b, 'anim', path, '-o', out + '.anim.crowdpack'] + guard,
        'lod': [b, 'lod', path, '-o', out + '.lod.crowdpack', '--poses', '2'] + guard,
        'impostor': [b, 'impostor', path, '-o', out + '.impostor.crowdpack', '--frames', '2',
                     '--views', '4x2', '--texels', '16'] + guard,
        'outfits': [b, 'outfits', path, '--outfit', 'self=' + path, '-o', out + '.outfits.crowdpack',
                    '--frame-step', '16', '--rays', '4'] + guard,
        'terrain': [b, 'terrain', path, '-o', out + '.terrain.crowdpack'] + guard,
        # the case as an outfit of its own unbroken body
        'outfit': [b, 'outfits', case.base, '--outfit', 'broken=' + path, '-o',
                   out + '.outfit.crowdpack', '--frame-step', '16', '--rays', '4'] + guard,
    }


def run_one(argv, max_rss, max_memory):
    out_path = argv[argv.index('-o') + 1]
    err_path = out_path + '.stderr'
    argv = argv + ['--max-memory', str(max_memory)]
    with open(err_path, 'wb') as err:
        p = subprocess.Popen(argv, stdout=subprocess.DEVNULL, stderr=err, start_new_session=True)
        timer = threading.Timer(GUARD + HANG_MARGIN, lambda: os.killpg(p.pid, signal.SIGKILL))
        timer.start()
        start = time.monotonic()
        _, status, usage = os.wait4(p.pid, 0)
        timer.cancel()
        p.returncode = status
        seconds = time.monotonic() - start
    stderr = open(err_path, 'rb').read().decode(errors='replace')
    lines = [l for l in stderr.splitlines() if l.strip()]
    rss = usage.ru_maxrss // 1024
    if os.WIFSIGNALED(status):
        outcome = 'hang' if seconds >= GUARD + HANG_MARGIN else 'crash'
    elif 'over --max-seconds' in stderr:
        outcome = 'hang'  # stopped by its own guard: the input kept it busy for GUARD seconds
    elif rss > max_rss or 'over --max-memory' in stderr:
        outcome = 'memory'
    elif 'Sanitizer' in stderr or 'runtime error:' in stderr:
        outcome = 'crash'
    else:
        code = os.WEXITSTATUS(status)
        if code == 0 and not [l for l in lines if not l.startswith('crowdbake: warning')]:
            # An accepted input must give a pack the reader takes whole.
            verify = subprocess.run([argv[0], 'verify', out_path], capture_output=True)
            outcome = 'accepted' if verify.returncode == 0 else 'bad pack'
        elif code in (1, 2) and len(lines) == 1 and lines[0].startswith(('crowdbake: error:', 'crowdbake: usage:')):
            outcome = 'handled'
        else:
            outcome = 'crash'
    return outcome, seconds, rss, lines[-1] if lines else ''


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument('bin_dir')
    ap.add_argument('work')
    ap.add_argument('--assets', default=os.path.join(HERE, '../../../shared/assets/gltf'))
    ap.add_argument('--jobs', type=int, default=os.cpu_count() or 2)
    ap.add_argument('--max-rss', type=int, default=1536, help='MiB (sanitizer builds: raise it)')
    ap.add_argument('--table', help='write the per-case table (Markdown) here')
    ap.add_argument('--rotate', action='store_true',
                    help='each case through anim and one other command in turn (lod, impostor, '
                         'outfits, terrain, outfit): every command still covered (CI budget)')
    ap.add_argument('--one', action='store_true',
                    help='each case through one command in turn (anim, lod, impostor, outfits, '
                         'terrain, outfit): every command still covered (sanitizer builds)')
    ap.add_argument('--every', type=int, default=1,
                    help='only every N-th case (sanitizer builds: 3, within CI\'s budget)')
    ap.add_argument('--only', help='only the cases whose name matches this regular expression')
    a = ap.parse_args()
    if not os.path.isdir(os.path.join(a.assets, 'RiggedSimple')):
        # As tests/scripts/skip.sh: a failure where CI promises the assets, else a skip (77).
        reason = f'the shared assets ({a.assets}) are not beside the checkout'
        if os.environ.get('CROWD_REQUIRE') == 'all':
            print(f'FAIL: CROWD_REQUIRE=all, but {reason}', file=sys.stderr)
            return 1
        print(f'SKIP: {reason}')
        return 77
    shutil.rmtree(a.work, ignore_errors=True)
    os.makedirs(a.work)
    cases = (build_cases(os.path.abspath(a.assets), None) +
             cache_cases(good_cache(os.path.abspath(a.bin_dir), a.work)))[::max(1, a.every)]
    if a.only:
        cases = [c for c in cases if re.search(a.only, c.name)]
    names = [c.name for c in cases]
    assert len(names) == len(set(names)), 'case names repeat'
    runs = []
    for c in cases:
        folder = os.path.join(a.work, c.name, 'asset')
        os.makedirs(folder)
        path = c.write(folder)
        chosen = commands(os.path.abspath(a.bin_dir), c, path, os.path.join(a.work, c.name, 'out'))
        i = names.index(c.name)
        if c.kind != 'gltf':
            pass  # one command reads a cloth cache
        elif a.one:
            only = GLTF_COMMANDS[i % len(GLTF_COMMANDS)]
            chosen = {only: chosen[only]}
        elif a.rotate:
            other = GLTF_COMMANDS[1 + i % (len(GLTF_COMMANDS) - 1)]
            chosen = {k: v for k, v in chosen.items() if k in ('anim', other)}
        for command, argv in chosen.items():
            runs.append((c.name, command, argv))
    print(f'campaign: {len(cases)} cases, {len(runs)} runs, {a.jobs} at a time', flush=True)
    results = {}
    with concurrent.futures.ThreadPoolExecutor(a.jobs) as pool:
        futures = {pool.submit(run_one, argv, a.max_rss, a.max_rss): (name, cmd)
                   for name, cmd, argv in runs}
        for f in concurrent.futures.as_completed(futures):
            results[futures[f]] = f.result()

    accepted_list = {}
    for line in open(os.path.join(HERE, 'accepted.txt')):
        if line.strip() and not line.startswith('#'):
            name, _, reason = line.partition(':')
            accepted_list[name.strip()] = reason.strip()
    totals = {}
    bad, unlisted = [], set()
    rows = []
    for name in names:
        row = [name]
        for command in GLTF_COMMANDS + ('cloth',):
            if (name, command) not in results:
                row.append('-')
                continue
            outcome, seconds, rss, last = results[(name, command)]
            totals.setdefault(command, {}).setdefault(outcome, 0)
            totals[command][outcome] += 1
            row.append(outcome)
            if outcome in ('crash', 'hang', 'memory', 'bad pack'):
                bad.append(f'{outcome}: {name} {command} ({seconds:.1f} s, {rss} MiB): {last}')
            if outcome == 'accepted' and name not in accepted_list:
                unlisted.add(name)
        rows.append(row)
    accepted_cases = {n for (n, _), r in results.items() if r[0] == 'accepted'}
    stale = sorted(set(accepted_list) - accepted_cases)

    kinds = ('handled', 'accepted', 'crash', 'hang', 'memory', 'bad pack')
    print('| command | ' + ' | '.join(kinds) + ' |')
    print('|---|' + '---|' * len(kinds))
    for command, t in totals.items():
        print(f'| {command} | ' + ' | '.join(str(t.get(k, 0)) for k in kinds) + ' |')
    by_time = sorted(results.items(), key=lambda kv: -kv[1][1])
    by_rss = sorted(results.items(), key=lambda kv: -kv[1][2])
    print('slowest runs: ' + ', '.join(f'{k[0]} {k[1]} {r[1]:.1f} s' for k, r in by_time[:5]))
    print('largest runs: ' + ', '.join(f'{k[0]} {k[1]} {r[2]} MiB' for k, r in by_rss[:3]))
    print(f'total run time {sum(r[1] for r in results.values()):.0f} s')
    if a.table:
        with open(a.table, 'w') as t:
            columns = GLTF_COMMANDS + ('cloth',)
            t.write('| case | ' + ' | '.join(columns) + ' |\n|---|' + '---|' * len(columns) + '\n')
            for row in rows:
                t.write('| ' + ' | '.join(row) + ' |\n')
    for b in bad:
        print('FAIL ' + b)
    for n in sorted(unlisted):
        print(f'FAIL accepted but not justified in accepted.txt: {n}')
    for n in stale:  # with --rotate or --one a listed case may not meet the command accepting it
        print(f'note: listed in accepted.txt but not accepted in this run: {n}')
    ok = not bad and not unlisted
    print('campaign: ' + ('passed' if ok else 'FAILED'))
    return 0 if ok else 1


if __name__ == '__main__':
    sys.exit(main())
