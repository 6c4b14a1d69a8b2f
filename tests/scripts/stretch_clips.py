#!/usr/bin/env python3
"""stretch_clips.py IN.glb OUT.glb FACTOR: every clip's key times times FACTOR, the common export
mistake of a take far longer than meant (the farm test's runaway job)."""
import json
import struct
import sys

src, dst, factor = sys.argv[1], sys.argv[2], float(sys.argv[3])
data = bytearray(open(src, 'rb').read())
json_len = struct.unpack_from('<I', data, 12)[0]
doc = json.loads(data[20:20 + json_len])
bin_start = 20 + json_len + 8  # the BIN chunk's payload
inputs = {s['input'] for a in doc.get('animations', []) for s in a['samplers']}
for i in inputs:
    acc = doc['accessors'][i]
    view = doc['bufferViews'][acc['bufferView']]
    at = bin_start + view.get('byteOffset', 0) + acc.get('byteOffset', 0)
    times = struct.unpack_from('<%df' % acc['count'], data, at)
    struct.pack_into('<%df' % acc['count'], data, at, *[t * factor for t in times])
    acc['min'] = [min(times) * factor]
    acc['max'] = [max(times) * factor]
text = json.dumps(doc, separators=(',', ':')).encode()
text += b' ' * ((4 - len(text) % 4) % 4)
out = data[:12] + struct.pack('<I4s', len(text), b'JSON') + text + data[20 + json_len:]
struct.pack_into('<I', out, 8, len(out))
open(dst, 'wb').write(out)
