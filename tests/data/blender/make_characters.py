# Writes the Blender-exported test characters beside this script (Debian's blender 3.4 and its
# glTF add-on: an exporter our own code did not write):
#   blender -b --factory-startup --python tests/data/blender/make_characters.py
# Each is built from primitives, skinned by a distance rule (not Blender's heat weights, which
# fail at random on disjoint parts), animated with several actions, and exported as .glb:
#   trooper_cm.glb  a humanoid modelled in centimetres under an armature scaled 0.01 (the
#                   FBX-import habit), a flat-shaded textured torso, smooth limbs, a helmet and a
#                   rifle parented rigidly to bones, five clips, at most 4 influences
#   crawler.glb     a six-legged creature in metres, flat-shaded everywhere, no texture, up to 8
#                   influences a vertex (JOINTS_1/WEIGHTS_1), three clips
#   robot.glb       rigid parts only: every part parented to a bone, no skin at all, two clips
#   morph_biped.gltf  (+ .bin, .png) shape keys, one animated, beside a skin; a second mesh on the
#                   same armature; Bezier keys exported as CUBICSPLINE
#   two_rigs.glb    two armatures, each skinning its own mesh: two skins in one file
#   mirrored.glb    rigid legs, the left the right one's copy under a negative scale (as modellers
#                   mirror a part): glTF winds its triangles clockwise; a flat-shaded boot each
#   ../keyed/keys.glb  clips exported as keyed, not sampled: CONSTANT keys (STEP), LINEAR keys
#                   at uneven subframe times 40-70 degrees apart, Bezier keys (CUBICSPLINE). Kept
#                   apart from the others: the animation texture cannot follow the first two
#                   within the budget (compressed joint tracks can), and every test over the
#                   real models holds the texture to it.
# The files are committed (tests must not need Blender); rerun this script to remake them (the
# same characters; the bytes may differ from run to run), or some of them by name:
#   blender -b --factory-startup --python tests/data/blender/make_characters.py -- mirrored
# Bench inputs (not committed) by name only, written into $CROWD_BLENDER_OUT:
#   many_clips.glb  a dense biped (23k triangles) with 24 clips (tests/bench/anim_speed.sh)
import math
import os
import sys

import numpy

numpy.bool = bool  # Blender 3.4's glTF add-on still uses the alias NumPy removed
import bmesh
import bpy
from mathutils import Matrix, Vector

HERE = os.path.dirname(os.path.abspath(__file__))


def reset():
    bpy.ops.wm.read_factory_settings(use_empty=True)


def armature(name, bones, scale=1.0):
    """bones: (name, parent, head, tail) in the armature's own units."""
    data = bpy.data.armatures.new(name)
    rig = bpy.data.objects.new(name, data)
    bpy.context.scene.collection.objects.link(rig)
    rig.scale = (scale, scale, scale)
    bpy.context.view_layer.objects.active = rig
    bpy.ops.object.mode_set(mode='EDIT')
    for bone, parent, head, tail in bones:
        e = data.edit_bones.new(bone)
        e.head, e.tail = Vector(head), Vector(tail)
        if parent:
            e.parent = data.edit_bones[parent]
    bpy.ops.object.mode_set(mode='OBJECT')
    return rig


def add_part(bm, kind, at, size, rotation=(0, 0, 0), segments=12, flat=False):
    """A primitive into bmesh `bm` (with its UVs): 'box', 'cylinder' (along z, ring cuts so it
    bends), 'sphere' or 'cone'."""
    matrix = Matrix.Translation(Vector(at)) @ Matrix.Rotation(rotation[2], 4, 'Z') @ \
        Matrix.Rotation(rotation[1], 4, 'Y') @ Matrix.Rotation(rotation[0], 4, 'X') @ \
        Matrix.Diagonal(Vector(size).to_4d())
    bm.loops.layers.uv.verify()  # calc_uvs writes into the mesh's UV layer
    before = set(bm.faces)
    if kind == 'box':
        bmesh.ops.create_cube(bm, size=1.0, matrix=matrix, calc_uvs=True)
    elif kind == 'sphere':
        bmesh.ops.create_uvsphere(bm, u_segments=segments, v_segments=segments // 2, radius=0.5,
                                  matrix=matrix, calc_uvs=True)
    elif kind == 'cone':
        bmesh.ops.create_cone(bm, cap_ends=True, segments=segments, radius1=0.5, radius2=0.0,
                              depth=1.0, matrix=matrix, calc_uvs=True)
    else:
        geom = bmesh.ops.create_cone(bm, cap_ends=True, segments=segments, radius1=0.5,
                                     radius2=0.5, depth=1.0, matrix=matrix, calc_uvs=True)
        edges = [e for e in bm.edges if e.verts[0] in geom['verts'] and e.verts[1] in
                 geom['verts'] and abs((e.verts[0].co - e.verts[1].co).normalized().dot(
                     (matrix.to_3x3() @ Vector((0, 0, 1))).normalized())) > 0.99]
        bmesh.ops.subdivide_edges(bm, edges=edges, cuts=5, use_grid_fill=False)
    for f in set(bm.faces) - before:
        f.smooth = not flat


def mesh_object(name, bm, parent, material=None):
    me = bpy.data.meshes.new(name)
    bm.to_mesh(me)
    bm.free()
    ob = bpy.data.objects.new(name, me)
    bpy.context.scene.collection.objects.link(ob)
    if material:
        me.materials.append(material)
    ob.parent = parent
    return ob


def skin(ob, rig, max_influences):
    """Weights from each vertex's distance to each bone segment (in the armature's units): the
    nearest `max_influences` bones, 1 / d^4, normalised."""
    bones = [(b.name, b.head_local.copy(), b.tail_local.copy()) for b in rig.data.bones]
    for name, _, _ in bones:
        ob.vertex_groups.new(name=name)
    for v in ob.data.vertices:
        p = v.co
        dist = []
        for name, a, b in bones:
            ab = b - a
            t = max(0.0, min(1.0, (p - a).dot(ab) / ab.length_squared))
            dist.append(((p - (a + ab * t)).length + 1e-3, name))
        dist.sort()
        near = dist[:max_influences]
        w = [1.0 / d ** 4 for d, _ in near]
        total = sum(w)
        for (d, name), wi in zip(near, w):
            ob.vertex_groups[name].add([v.index], wi / total, 'REPLACE')
    mod = ob.modifiers.new('Armature', 'ARMATURE')
    mod.object = rig


def rigid(ob, rig, bone):
    """Parent `ob` to `bone`, keeping where it is (modelled under the rig: in its units)."""
    bpy.context.view_layer.update()
    world = ob.matrix_world.copy()
    ob.parent = rig
    ob.parent_type = 'BONE'
    ob.parent_bone = bone
    bpy.context.view_layer.update()
    ob.matrix_world = world


def action(rig, name, seconds, keys):
    """keys: bone -> list of (time s, euler xyz radians); a looping action pushed to its own NLA
    track (the exporter writes one animation per track)."""
    fps = bpy.context.scene.render.fps
    rig.animation_data_create()
    act = bpy.data.actions.new(name)
    rig.animation_data.action = act
    for bone, frames in keys.items():
        pb = rig.pose.bones[bone]
        pb.rotation_mode = 'XYZ'
        for t, euler in frames:
            pb.rotation_euler = euler
            pb.keyframe_insert('rotation_euler', frame=1 + t * fps)
    for pb in rig.pose.bones:
        pb.rotation_euler = (0, 0, 0)
    track = rig.animation_data.nla_tracks.new()
    track.name = name
    track.strips.new(name, 1, act)
    rig.animation_data.action = None


def cycle(amplitude, seconds, phase=0.0, axis=0, steps=8):
    """A looping swing about one axis, `steps` keys (the last equal to the first)."""
    out = []
    for k in range(steps + 1):
        t = seconds * k / steps
        e = [0.0, 0.0, 0.0]
        e[axis] = amplitude * math.sin(2 * math.pi * k / steps + phase)
        out.append((t, tuple(e)))
    return out


def texture_material(name):
    img = bpy.data.images.new(name + '_tex', 64, 64)
    pixels = []
    for y in range(64):
        for x in range(64):
            check = ((x // 8) + (y // 8)) % 2
            pixels += [0.2 + 0.6 * check, 0.3 + 0.4 * (y / 63), 0.25 + 0.5 * (x / 63), 1.0]
    img.pixels = pixels
    img.pack()
    mat = bpy.data.materials.new(name)
    mat.use_nodes = True
    tex = mat.node_tree.nodes.new('ShaderNodeTexImage')
    tex.image = img
    bsdf = mat.node_tree.nodes['Principled BSDF']
    mat.node_tree.links.new(tex.outputs['Color'], bsdf.inputs['Base Color'])
    return mat


def plain_material(name, rgb):
    mat = bpy.data.materials.new(name)
    mat.use_nodes = True
    mat.node_tree.nodes['Principled BSDF'].inputs['Base Color'].default_value = (*rgb, 1.0)
    return mat


def export(path, **options):
    options.setdefault('export_format', 'GLB')
    bpy.ops.export_scene.gltf(filepath=path, export_animations=True, export_nla_strips=True,
                              export_skins=True, export_apply=False, **options)
    print('wrote', path)


def trooper():
    reset()
    cm = 100.0  # modelled in centimetres, the armature scaled 0.01
    L = [('hips', None, (0, 0, 95), (0, 0, 110)), ('spine', 'hips', (0, 0, 110), (0, 0, 130)),
         ('chest', 'spine', (0, 0, 130), (0, 0, 150)), ('neck', 'chest', (0, 0, 150), (0, 0, 160)),
         ('head', 'neck', (0, 0, 160), (0, 0, 185))]
    for s, x in (('L', 1), ('R', -1)):
        L += [(f'upperarm.{s}', 'chest', (x * 20, 0, 148), (x * 45, 0, 148)),
              (f'forearm.{s}', f'upperarm.{s}', (x * 45, 0, 148), (x * 68, 0, 148)),
              (f'hand.{s}', f'forearm.{s}', (x * 68, 0, 148), (x * 78, 0, 148)),
              (f'thigh.{s}', 'hips', (x * 10, 0, 95), (x * 10, 0, 50)),
              (f'shin.{s}', f'thigh.{s}', (x * 10, 0, 50), (x * 10, 0, 8)),
              (f'foot.{s}', f'shin.{s}', (x * 10, 0, 8), (x * 10, -15, 2))]
    rig = armature('TrooperRig', L, scale=1 / cm)
    skin_mat = texture_material('Uniform')
    bm = bmesh.new()
    add_part(bm, 'box', (0, 0, 127), (36, 22, 50), flat=True)  # torso: flat-shaded
    add_part(bm, 'sphere', (0, 0, 170), (22, 24, 26), segments=16)
    for x in (1, -1):
        add_part(bm, 'cylinder', (x * 46, 0, 148), (9, 9, 56), rotation=(0, math.pi / 2, 0))
        add_part(bm, 'cylinder', (x * 10, 0, 52), (13, 13, 90))
        add_part(bm, 'box', (x * 10, -6, 3), (11, 22, 6), flat=True)
    body = mesh_object('Trooper', bm, rig, skin_mat)
    skin(body, rig, 4)
    helmet_bm = bmesh.new()
    add_part(helmet_bm, 'sphere', (0, 0, 176), (27, 29, 20), segments=12, flat=True)
    helmet = mesh_object('Helmet', helmet_bm, rig, plain_material('Helmet', (0.2, 0.3, 0.2)))
    rigid(helmet, rig, 'head')
    rifle_bm = bmesh.new()
    add_part(rifle_bm, 'box', (-74, -25, 148), (5, 70, 8), flat=True)
    rifle = mesh_object('Rifle', rifle_bm, rig, plain_material('Rifle', (0.1, 0.1, 0.1)))
    rigid(rifle, rig, 'hand.R')
    action(rig, 'walk', 1.0, {'thigh.L': cycle(0.5, 1.0), 'thigh.R': cycle(0.5, 1.0, math.pi),
                              'shin.L': cycle(0.4, 1.0, -1.0), 'shin.R': cycle(0.4, 1.0, 2.1),
                              'upperarm.L': cycle(0.4, 1.0, math.pi, 2),
                              'upperarm.R': cycle(0.4, 1.0, 0.0, 2)})
    action(rig, 'run', 0.6, {'thigh.L': cycle(0.9, 0.6), 'thigh.R': cycle(0.9, 0.6, math.pi),
                             'shin.L': cycle(0.9, 0.6, -1.0), 'shin.R': cycle(0.9, 0.6, 2.1),
                             'forearm.L': cycle(0.8, 0.6, 0.0, 2),
                             'forearm.R': cycle(0.8, 0.6, math.pi, 2)})
    action(rig, 'wave', 2.0, {'upperarm.L': cycle(0.3, 2.0, 0.0, 1, 4),
                              'forearm.L': cycle(1.2, 2.0, 0.0, 0, 8)})
    action(rig, 'idle', 3.0, {'spine': cycle(0.05, 3.0, 0.0, 0, 4),
                              'head': cycle(0.3, 3.0, 0.0, 2, 4)})
    action(rig, 'crouch', 1.5, {'thigh.L': [(0, (0, 0, 0)), (0.75, (1.2, 0, 0)), (1.5, (0, 0, 0))],
                                'thigh.R': [(0, (0, 0, 0)), (0.75, (1.2, 0, 0)), (1.5, (0, 0, 0))],
                                'shin.L': [(0, (0, 0, 0)), (0.75, (-2.0, 0, 0)), (1.5, (0, 0, 0))],
                                'shin.R': [(0, (0, 0, 0)), (0.75, (-2.0, 0, 0)), (1.5, (0, 0, 0))]})
    export(os.path.join(HERE, 'trooper_cm.glb'))


def crawler():
    reset()
    bones = [('body', None, (0, -0.4, 0.3), (0, 0.4, 0.3)), ('head', 'body', (0, 0.4, 0.3),
                                                             (0, 0.65, 0.35))]
    for i, y in enumerate((-0.3, 0.0, 0.3)):
        for s, x in (('L', 1), ('R', -1)):
            bones += [(f'leg{i}.{s}', 'body', (x * 0.15, y, 0.3), (x * 0.45, y, 0.35)),
                      (f'foot{i}.{s}', f'leg{i}.{s}', (x * 0.45, y, 0.35), (x * 0.6, y, 0.0))]
    rig = armature('CrawlerRig', bones)
    bm = bmesh.new()
    add_part(bm, 'cylinder', (0, 0, 0.3), (0.3, 0.3, 0.9), rotation=(math.pi / 2, 0, 0),
             segments=8, flat=True)
    add_part(bm, 'cone', (0, 0.6, 0.32), (0.22, 0.22, 0.3), rotation=(-math.pi / 2, 0, 0),
             segments=8, flat=True)
    for y in (-0.3, 0.0, 0.3):
        for x in (1, -1):
            add_part(bm, 'cylinder', (x * 0.38, y, 0.32), (0.06, 0.06, 0.46),
                     rotation=(0, math.pi / 2, 0), segments=6, flat=True)
            add_part(bm, 'cylinder', (x * 0.52, y, 0.17), (0.05, 0.05, 0.38),
                     rotation=(0, x * 0.45, 0), segments=6, flat=True)
    body = mesh_object('Crawler', bm, rig, plain_material('Shell', (0.5, 0.35, 0.1)))
    skin(body, rig, 8)
    keys = {}
    for i in range(3):
        for s, ph in (('L', 0.0), ('R', math.pi)):
            keys[f'leg{i}.{s}'] = cycle(0.4, 0.8, ph + i * 2.1, 2)
            keys[f'foot{i}.{s}'] = cycle(0.3, 0.8, ph + i * 2.1 + 1.5, 1)
    action(rig, 'scuttle', 0.8, keys)
    action(rig, 'look', 2.0, {'head': cycle(0.5, 2.0, 0.0, 2, 4), 'body': cycle(0.1, 2.0, 0.0, 1, 4)})
    action(rig, 'rear', 1.2, {'body': [(0, (0, 0, 0)), (0.6, (0.5, 0, 0)), (1.2, (0, 0, 0))]})
    export(os.path.join(HERE, 'crawler.glb'), export_all_influences=True)


def robot():
    reset()
    bones = [('base', None, (0, 0, 0), (0, 0, 0.5)), ('arm', 'base', (0, 0, 0.5), (0, 0, 1.1)),
             ('fore', 'arm', (0, 0, 1.1), (0, 0, 1.6)), ('grip', 'fore', (0, 0, 1.6), (0, 0, 1.8))]
    rig = armature('RobotRig', bones)
    parts = [('Base', 'base', 'box', (0, 0, 0.2), (0.6, 0.6, 0.4)),
             ('Arm', 'arm', 'cylinder', (0, 0, 0.8), (0.15, 0.15, 0.6)),
             ('Fore', 'fore', 'cylinder', (0, 0, 1.35), (0.12, 0.12, 0.5)),
             ('Grip', 'grip', 'cone', (0, 0, 1.7), (0.2, 0.2, 0.2))]
    for name, bone, kind, at, size in parts:
        bm = bmesh.new()
        add_part(bm, kind, at, size, segments=10, flat=kind == 'box')
        ob = mesh_object(name, bm, None, plain_material(name, (0.6, 0.6, 0.65)))
        rigid(ob, rig, bone)
    action(rig, 'work', 2.0, {'arm': cycle(0.6, 2.0, 0.0, 0, 8), 'fore': cycle(0.9, 2.0, 1.0, 0, 8),
                              'base': cycle(1.0, 2.0, 0.0, 2, 8)})
    action(rig, 'rest', 1.0, {'arm': [(0, (0.2, 0, 0)), (1.0, (0.2, 0, 0))]})
    export(os.path.join(HERE, 'robot.glb'))


def morph_biped():
    """Shape keys (one animated), a second mesh on the same armature, keys kept as Blender's
    Bezier curves (CUBICSPLINE), written as .gltf + .bin + .png."""
    reset()
    bones = [('root', None, (0, 0, 0.0), (0, 0, 0.9)), ('spine', 'root', (0, 0, 0.9), (0, 0, 1.4)),
             ('head', 'spine', (0, 0, 1.4), (0, 0, 1.8))]
    rig = armature('MorphRig', bones)
    bm = bmesh.new()
    add_part(bm, 'cylinder', (0, 0, 0.7), (0.4, 0.4, 1.4), segments=16)
    add_part(bm, 'sphere', (0, 0, 1.6), (0.4, 0.4, 0.4), segments=16)
    body = mesh_object('MorphBody', bm, rig, texture_material('Skin'))
    bm = bmesh.new()
    add_part(bm, 'box', (0, -0.25, 1.0), (0.3, 0.1, 0.3), flat=True)
    backpack = mesh_object('Backpack', bm, rig, plain_material('Pack', (0.1, 0.2, 0.6)))
    skin(body, rig, 4)
    skin(backpack, rig, 2)
    body.shape_key_add(name='Basis')
    bulge = body.shape_key_add(name='bulge')
    for v in bulge.data:
        if 0.3 < v.co.z < 1.3:
            v.co.x *= 1.3
            v.co.y *= 1.3
    squash = body.shape_key_add(name='squash')
    for v in squash.data:
        v.co.z *= 0.9
    keys = body.data.shape_keys
    keys.animation_data_create()
    keys.animation_data.action = bpy.data.actions.new('breathe')
    for t, w in ((0, 0.0), (1, 1.0), (2, 0.0)):
        bulge.value = w
        bulge.keyframe_insert('value', frame=1 + t * 24)
    action(rig, 'sway', 2.0, {'spine': cycle(0.3, 2.0, 0.0, 1, 8),
                              'head': cycle(0.4, 2.0, 1.0, 2, 8)})
    export(os.path.join(HERE, 'morph_biped.gltf'), export_format='GLTF_SEPARATE',
           export_morph=True, export_force_sampling=False)


def two_rigs():
    """Two armatures, each skinning its own tube: two skins in one file."""
    reset()
    rigs = [armature('RigA', [('a0', None, (0, 0, 0), (0, 0, 0.5)),
                              ('a1', 'a0', (0, 0, 0.5), (0, 0, 1.0))]),
            armature('RigB', [('b0', None, (1, 0, 0), (1, 0, 0.5)),
                              ('b1', 'b0', (1, 0, 0.5), (1, 0, 1.0))])]
    for x, rig in enumerate(rigs):
        bm = bmesh.new()
        add_part(bm, 'cylinder', (x, 0, 0.5), (0.2, 0.2, 1.0), segments=8)
        tube = mesh_object('Tube' + rig.name, bm, rig,
                           plain_material('M' + rig.name, (0.5, 0.5, 0.2 + x * 0.5)))
        skin(tube, rig, 4)
    action(rigs[0], 'bendA', 1.0, {'a1': cycle(0.8, 1.0, 0.0, 0, 8)})
    action(rigs[1], 'bendB', 1.0, {'b1': cycle(0.8, 1.0, 0.0, 1, 8)})
    export(os.path.join(HERE, 'two_rigs.glb'))


def mirrored():
    """Two rigid legs on a hip bone: the left one the right one's mesh under a scale of -1 in x."""
    reset()
    bones = [('hips', None, (0, 0, 1.0), (0, 0, 1.2)),
             ('leg_r', 'hips', (0.2, 0, 1.0), (0.2, 0, 0.1)),
             ('leg_l', 'hips', (-0.2, 0, 1.0), (-0.2, 0, 0.1))]
    rig = armature('MirrorRig', bones)
    bm = bmesh.new()
    add_part(bm, 'box', (0, 0, 1.1), (0.6, 0.3, 0.2), flat=True)
    rigid(mesh_object('Hips', bm, None, plain_material('Hips', (0.3, 0.3, 0.3))), rig, 'hips')
    for side, x, bone in (('R', 1, 'leg_r'), ('L', -1, 'leg_l')):
        bm = bmesh.new()  # around the leg's own origin, the boot off-centre so that it mirrors
        add_part(bm, 'cylinder', (0, 0, 0), (0.16, 0.16, 0.9), segments=10)
        add_part(bm, 'box', (0.04, 0.08, -0.45), (0.2, 0.32, 0.12), flat=True)
        leg = mesh_object('Leg' + side, bm, None, plain_material('Leg', (0.2, 0.3, 0.6)))
        leg.location = (0.2 * x, 0, 0.55)
        leg.scale = (x, 1, 1)
        rigid(leg, rig, bone)
    action(rig, 'walk', 1.0, {'leg_r': cycle(0.5, 1.0, 0.0, 0, 8),
                              'leg_l': cycle(0.5, 1.0, math.pi, 0, 8)})
    export(os.path.join(HERE, 'mirrored.glb'))


def keys():
    """Clips keyed as an animator keys them and exported as keyed (no sampling): 'steps' in
    CONSTANT keys (STEP), 'turns' in LINEAR keys at uneven subframe times, 40 to 70 degrees apart
    (a fast robot's), 'swing' in Bezier keys (CUBICSPLINE)."""
    reset()
    bones = [('root', None, (0, 0, 0.0), (0, 0, 0.8)), ('spine', 'root', (0, 0, 0.8), (0, 0, 1.3)),
             ('head', 'spine', (0, 0, 1.3), (0, 0, 1.8)),
             ('arm', 'spine', (0.1, 0, 1.25), (0.7, 0, 1.25))]
    rig = armature('KeysRig', bones)
    bm = bmesh.new()
    add_part(bm, 'cylinder', (0, 0, 0.65), (0.35, 0.35, 1.3), segments=12)
    add_part(bm, 'sphere', (0, 0, 1.55), (0.35, 0.35, 0.4), segments=12)
    add_part(bm, 'cylinder', (0.4, 0, 1.25), (0.1, 0.1, 0.6), rotation=(0, math.pi / 2, 0),
             segments=8)
    skin(mesh_object('KeysBody', bm, rig, plain_material('Keys', (0.6, 0.4, 0.3))), rig, 4)
    action(rig, 'steps', 2.0, {
        'spine': [(0, (0, 0, 0)), (0.5, (0.5, 0, 0)), (1.1, (-0.4, 0, 0)), (2.0, (0, 0, 0))],
        'arm': [(0, (0, 0, 0)), (0.7, (0, 0, 1.0)), (1.4, (0, 0, -0.6)), (2.0, (0, 0, 0))]})
    turns, t, angle = [], 0.0, 0.0
    for k in range(24):  # steps of 19-37 ms (subframes at 24 fps), alternating turns
        turns.append((t, (0, 0, angle)))
        t += 0.019 + 0.018 * ((k * 7) % 5) / 4
        angle += math.radians(40 + 30 * ((k * 3) % 4) / 3) * (1 if k % 2 == 0 else -0.8)
    action(rig, 'turns', t, {'spine': turns, 'head': [(tk, (a[2] * 0.5, 0, 0)) for tk, a in turns]})
    action(rig, 'swing', 2.0, {'spine': cycle(0.5, 2.0, 0.0, 1, 4),
                               'arm': cycle(0.9, 2.0, 1.0, 2, 4)})
    for name, mode in (('steps', 'CONSTANT'), ('turns', 'LINEAR')):
        for fc in bpy.data.actions[name].fcurves:
            for key in fc.keyframe_points:
                key.interpolation = mode
    export(os.path.join(HERE, '..', 'keyed', 'keys.glb'), export_force_sampling=False)


def many_clips():
    """A bench input, not committed (tests/bench/anim_speed.sh makes it): a dense biped (23k
    triangles, smooth) with 24 clips of 0.5-2.8 s, every bone keyed, every fourth clip in steps
    (CONSTANT keys): a library character with many clips."""
    reset()
    bones = [('root', None, (0, 0, 0.9), (0, 0, 1.1)), ('spine', 'root', (0, 0, 1.1), (0, 0, 1.4)),
             ('head', 'spine', (0, 0, 1.4), (0, 0, 1.7))]
    for s, x in (('L', 1), ('R', -1)):
        bones += [(f'arm.{s}', 'spine', (x * 0.2, 0, 1.35), (x * 0.5, 0, 1.35)),
                  (f'fore.{s}', f'arm.{s}', (x * 0.5, 0, 1.35), (x * 0.75, 0, 1.35)),
                  (f'leg.{s}', 'root', (x * 0.1, 0, 0.9), (x * 0.1, 0, 0.5)),
                  (f'shin.{s}', f'leg.{s}', (x * 0.1, 0, 0.5), (x * 0.1, 0, 0.05))]
    rig = armature('Rig', bones)
    bm = bmesh.new()
    add_part(bm, 'cylinder', (0, 0, 1.15), (0.35, 0.22, 0.55), segments=32)
    add_part(bm, 'sphere', (0, 0, 1.55), (0.22, 0.22, 0.28), segments=32)
    for x in (1, -1):
        add_part(bm, 'cylinder', (x * 0.47, 0, 1.35), (0.1, 0.1, 0.6),
                 rotation=(0, math.pi / 2, 0), segments=24)
        add_part(bm, 'cylinder', (x * 0.1, 0, 0.47), (0.13, 0.13, 0.86), segments=24)
    bmesh.ops.subdivide_edges(bm, edges=bm.edges[:], cuts=2, use_grid_fill=True)
    bmesh.ops.triangulate(bm, faces=bm.faces[:])
    body = mesh_object('Body', bm, rig, texture_material('Skin'))
    skin(body, rig, 4)
    for k in range(24):
        seconds = 0.5 + 0.1 * k
        keys = {}
        for j, pb in enumerate(rig.pose.bones):
            keys[pb.name] = [(seconds * step / 8, (0.6 * math.sin(2 * math.pi * step / 8 + j + k),
                                                   0.2 * (k % 3) * math.sin(j + step), 0))
                             for step in range(9)]
        action(rig, f'clip{k:02d}', seconds, keys)
        if k % 4 == 3:
            for fc in bpy.data.actions[f'clip{k:02d}'].fcurves:
                for key in fc.keyframe_points:
                    key.interpolation = 'CONSTANT'
    export(os.path.join(OUT, 'many_clips.glb'))


MAKERS = {'trooper': trooper, 'crawler': crawler, 'robot': robot, 'morph_biped': morph_biped,
          'two_rigs': two_rigs, 'mirrored': mirrored, 'keys': keys}
BENCH_MAKERS = {'many_clips': many_clips}  # by name only, into $CROWD_BLENDER_OUT
OUT = os.environ.get('CROWD_BLENDER_OUT', HERE)
for name in sys.argv[sys.argv.index('--') + 1:] if '--' in sys.argv else MAKERS:
    {**MAKERS, **BENCH_MAKERS}[name]()
