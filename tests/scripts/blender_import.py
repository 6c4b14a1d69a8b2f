# Run by Blender (blender -b --python blender_import.py -- FILE...): imports each glTF with
# Blender's own importer and prints a line per file, "RESULT {json}": the joints its skinned mesh
# is bound to (vertex groups) and the animations it made (NLA tracks of the armature).
import json
import sys

import numpy

numpy.bool = bool  # Blender 3.4's glTF add-on still names it; numpy 1.24 dropped the alias
import bpy

for path in sys.argv[sys.argv.index('--') + 1:]:
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.ops.import_scene.gltf(filepath=path)
    armatures = [o for o in bpy.data.objects if o.type == 'ARMATURE']
    meshes = [o for o in bpy.data.objects if o.type == 'MESH']
    clips = sorted({t.name for a in armatures if a.animation_data for t in a.animation_data.nla_tracks})
    print('RESULT ' + json.dumps({'file': path, 'joints': max((len(m.vertex_groups) for m in meshes), default=0),
                                  'clips': clips}), flush=True)
