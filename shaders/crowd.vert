#version 450 core
// Skinned instancing: joint transforms come from the animation texture (two frames, blended
// exactly as runtime/src/texture_skinning.cpp does on the CPU), ids and weights from the
// skin-weight texture, per-instance data from one buffer indexed by the instance's id (an instanced
// attribute). An instance changing clip crossfades: both clips' joints blend as dual quaternions
// (blendJoints in runtime/src/texture_skinning.cpp).
// With compressed joint tracks (u_palettes), the joints come from skinning palettes instead:
// the palette pass (shaders/palette.comp) decoded one per distinct clip time (a crossfade's
// blended there), and each instance names its own.
// A garment with a cloth loop plays the loop's frames instead of its skinning: rigidly on the
// top joint, the loop frame following the body clip's phase (runtime/src/cloth_playback.cpp is
// the CPU mirror); its normal comes from the screen-space derivatives (v_facet).

layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;
layout(location = 2) in vec2 a_uv;
layout(location = 3) in uint a_instance; // per instance: which one (culled and sorted by level)

layout(binding = 0) uniform sampler2D u_animation; // RGBA32F or RGBA16F texels
layout(binding = 1) uniform sampler2D u_skin;      // RGBA32F: ids, weights

struct Instance {
  vec4 rows[3]; // world transform, 3x4
  vec4 params;  // clip, time offset (s), speed, palette
  vec4 fade;    // clip faded from (-1: none), its time offset (s), fade start (s), fade length (s)
};
layout(std430, binding = 0) readonly buffer Clips { vec4 clips[]; }; // fps, frames, first, loop
layout(std430, binding = 1) readonly buffer Instances { Instance instances[]; };
layout(std430, binding = 2) readonly buffer Palettes { vec4 colours[]; };
// Morph targets (runtime::morphSlotWords): per animation frame kMorphSlots slots (first offset
// pair, first vertex, vertex count, weight bits), and per target vertex a position and a normal
// offset.
layout(std430, binding = 3) readonly buffer MorphSlots { ivec4 morphSlots[]; };
layout(std430, binding = 4) readonly buffer MorphOffsets { vec4 morphOffsets[]; };
const int kMorphSlots = 8; // pack::kMorphSlots
// Cloth loops (runtime::ClothBuffers): per mesh vertex its garment and loop vertex (-1: none),
// per (garment, clip) a loop, per vertex-frame a 16-bit position (x | y << 16, z).
struct ClothLoop {
  ivec4 shape;  // first vertex-frame, vertices, frames (0: none), cycles
  vec4 origin;  // xyz; w: the loop's start in clip cycles
  vec4 spacing; // xyz: the quantisation step; w: cache frames per clip cycle
};
layout(std430, binding = 5) readonly buffer ClothVertices { ivec2 clothVertices[]; };
layout(std430, binding = 6) readonly buffer ClothLoops { ClothLoop clothLoops[]; };
layout(std430, binding = 7) readonly buffer ClothPositions { uvec2 clothPositions[]; };
layout(std430, binding = 8) readonly buffer JointTexels { ivec2 jointTexels[]; };
layout(std430, binding = 9) readonly buffer JointPalettes { vec4 paletteRows[]; }; // 3 per joint
layout(std430, binding = 10) readonly buffer InstancePalettes { int paletteOf[]; };

uniform mat4 u_viewProjection;
uniform float u_time;
uniform int u_frameTexels; // texels of one frame of every joint
uniform int u_framesPerRow;
uniform int u_skinWidth;
uniform int u_subMesh;
uniform int u_subMeshCount;
uniform bool u_morphs;    // the pack has morph targets
uniform bool u_cloth;     // the pack has cloth loops
uniform int u_clothClips; // the pack's clips (the loop table's stride)
uniform int u_rootJoint;
uniform bool u_palettes; // joints from palettes (compressed joint tracks), not the texture
uniform int u_joints;    // joints per palette
uniform int u_palette;   // the naive path's instance's palette
uniform mat4 u_rootBind; // the top joint's bind matrix
// Naive path: one draw per instance, its data in uniforms instead of the buffer.
uniform bool u_naive;
uniform vec4 u_rows[3];
uniform vec4 u_params[2]; // an Instance's params and fade
// A world's shadow pass: xyz towards the light, w = 1: every vertex goes along the light onto
// the ground the instance stands on (its translation's height), 2 cm up.
uniform vec4 u_shadow;

out vec3 v_normal;
out vec4 v_colour; // A: how much the diffuse texture applies
out vec2 v_uv;
out vec3 v_world;
out float v_facet; // 1: a cloth or flat-shaded vertex, shaded by its face's normal

// A joint's first texel in a frame and its texels: 3 (matrix rows) or 2 (quaternion, then
// translation and scale); jointTexelWords in runtime/src/texture_skinning.cpp.
ivec2 texelOf(int frame, int joint, int texel) {
  return ivec2((frame % u_framesPerRow) * u_frameTexels + jointTexels[joint].x + texel,
               frame / u_framesPerRow);
}

bool isMatrix(int joint) { return jointTexels[joint].y == 3; }

mat3x4 rowsFromQts(vec4 q, vec4 ts) {
  float x = q.x, y = q.y, z = q.z, w = q.w, s = ts.w;
  return mat3x4(
      vec4(s * (1 - 2 * (y * y + z * z)), s * 2 * (x * y - w * z), s * 2 * (x * z + w * y), ts.x),
      vec4(s * 2 * (x * y + w * z), s * (1 - 2 * (x * x + z * z)), s * 2 * (y * z - w * x), ts.y),
      vec4(s * 2 * (x * z - w * y), s * 2 * (y * z + w * x), s * (1 - 2 * (x * x + y * y)), ts.z));
}

// Hamilton product of quaternions stored (x, y, z, w).
vec4 qmul(vec4 a, vec4 b) {
  return vec4(a.w * b.xyz + b.w * a.xyz + cross(a.xyz, b.xyz), a.w * b.w - dot(a.xyz, b.xyz));
}

struct Rigid {
  vec4 real, dual; // unit dual quaternion: rotation and translation
  float scale;
};

Rigid mixRigid(Rigid a, Rigid b, float w) {
  if (dot(a.real, b.real) < 0) {
    b.real = -b.real;
    b.dual = -b.dual;
  }
  vec4 real = mix(a.real, b.real, w);
  float len = length(real);
  return Rigid(real / len, mix(a.dual, b.dual, w) / len, mix(a.scale, b.scale, w));
}

mat3x4 rowsOf(Rigid r) {
  vec3 translation = 2.0 * qmul(r.dual, vec4(-r.real.xyz, r.real.w)).xyz;
  return rowsFromQts(r.real, vec4(translation, r.scale));
}

Rigid rigidOfQts(vec4 q, vec4 ts) { return Rigid(q, 0.5 * qmul(vec4(ts.xyz, 0), q), ts.w); }

// Scale: the columns' mean length; rotation: the scaled 3x3 part's quaternion (Shepperd).
Rigid rigidOf(mat3x4 m) {
  float scale = (length(vec3(m[0].x, m[1].x, m[2].x)) + length(vec3(m[0].y, m[1].y, m[2].y)) +
                 length(vec3(m[0].z, m[1].z, m[2].z))) /
                3.0;
  mat3x4 r = m * (1.0 / scale);
  vec4 q;
  float trace = r[0].x + r[1].y + r[2].z;
  if (trace > 0) {
    float s = 2.0 * sqrt(trace + 1.0);
    q = vec4((r[2].y - r[1].z) / s, (r[0].z - r[2].x) / s, (r[1].x - r[0].y) / s, 0.25 * s);
  } else if (r[0].x > r[1].y && r[0].x > r[2].z) {
    float s = 2.0 * sqrt(1.0 + r[0].x - r[1].y - r[2].z);
    q = vec4(0.25 * s, (r[0].y + r[1].x) / s, (r[0].z + r[2].x) / s, (r[2].y - r[1].z) / s);
  } else if (r[1].y > r[2].z) {
    float s = 2.0 * sqrt(1.0 + r[1].y - r[0].x - r[2].z);
    q = vec4((r[0].y + r[1].x) / s, 0.25 * s, (r[1].z + r[2].y) / s, (r[0].z - r[2].x) / s);
  } else {
    float s = 2.0 * sqrt(1.0 + r[2].z - r[0].x - r[1].y);
    q = vec4((r[0].z + r[2].x) / s, (r[1].z + r[2].y) / s, 0.25 * s, (r[1].x - r[0].y) / s);
  }
  q = normalize(q);
  return Rigid(q, 0.5 * qmul(vec4(m[0].w, m[1].w, m[2].w, 0), q), scale);
}

Rigid frameRigid(int frame, int joint) {
  if (isMatrix(joint))
    return rigidOf(mat3x4(texelFetch(u_animation, texelOf(frame, joint, 0), 0),
                          texelFetch(u_animation, texelOf(frame, joint, 1), 0),
                          texelFetch(u_animation, texelOf(frame, joint, 2), 0)));
  return rigidOfQts(texelFetch(u_animation, texelOf(frame, joint, 0), 0),
                    texelFetch(u_animation, texelOf(frame, joint, 1), 0));
}

// A joint between two frames as a rigid transform, each frame converted on its own.
Rigid jointRigid(int f0, int f1, float alpha, int joint) {
  return mixRigid(frameRigid(f0, joint), frameRigid(f1, joint), alpha);
}

mat3x4 jointRows(int f0, int f1, float alpha, int joint) {
  if (isMatrix(joint)) {
    return mat3x4(mix(texelFetch(u_animation, texelOf(f0, joint, 0), 0),
                      texelFetch(u_animation, texelOf(f1, joint, 0), 0), alpha),
                  mix(texelFetch(u_animation, texelOf(f0, joint, 1), 0),
                      texelFetch(u_animation, texelOf(f1, joint, 1), 0), alpha),
                  mix(texelFetch(u_animation, texelOf(f0, joint, 2), 0),
                      texelFetch(u_animation, texelOf(f1, joint, 2), 0), alpha));
  }
  // Dual-quaternion (screw-linear) blend of rotation and translation; scale blends linearly.
  return rowsOf(jointRigid(f0, f1, alpha, joint));
}

mat3x4 paletteJoint(int palette, int joint) {
  int k = (palette * u_joints + joint) * 3;
  return mat3x4(paletteRows[k], paletteRows[k + 1], paletteRows[k + 2]);
}

// The two frames of a clip around scene time u_time and the blend between them.
struct ClipTime {
  int f0, f1;
  float alpha;
};

ClipTime clipTime(float clipIndex, float offset, float speed) {
  vec4 clip = clips[int(clipIndex)]; // fps, frames, first, loop
  float last = clip.y - 1.0;
  float f = (u_time * speed + offset) * clip.x;
  if (clip.w > 0.5 && last > 0 && (f < 0.0 || f > last)) // past the end: frameAt's rule
    f = f - last * floor(f / last);
  f = clamp(f, 0.0, last);
  int frame = int(floor(f));
  return ClipTime(int(clip.z) + min(frame, int(last)), int(clip.z) + min(frame + 1, int(last)),
                  f - float(frame));
}

// Adds `factor` times the offsets of frame `frame`'s active morph targets (addMorphs in
// runtime/src/texture_skinning.cpp).
void addMorphs(int frame, float factor, inout vec3 p, inout vec3 n) {
  for (int s = 0; s < kMorphSlots; ++s) {
    ivec4 slot = morphSlots[frame * kMorphSlots + s];
    float w = intBitsToFloat(slot.w) * factor;
    int local = gl_VertexID - slot.y;
    if (w == 0.0 || local < 0 || local >= slot.z)
      continue;
    int k = 2 * (slot.x + local);
    p += w * morphOffsets[k].xyz;
    n += w * morphOffsets[k + 1].xyz;
  }
}

void addMorphs(ClipTime t, float factor, inout vec3 p, inout vec3 n) {
  addMorphs(t.f0, factor * (1.0 - t.alpha), p, n);
  addMorphs(t.f1, factor * t.alpha, p, n);
}

// Cloth loop vertex `v`'s bind-pose position at the instance's clip time (clipIndex, offset,
// speed), if its garment has a loop over that clip (loopTimeAt, clothBindPosition).
bool clothAt(float clipIndex, float offset, float speed, ivec2 v, out vec3 bindPosition) {
  ClothLoop loop = clothLoops[v.x * u_clothClips + int(clipIndex)];
  if (loop.shape.z == 0)
    return false;
  vec4 clip = clips[int(clipIndex)];
  float last = clip.y - 1.0;
  float u = last > 0.0 ? (u_time * speed + offset) * clip.x / last : 0.0;
  if (clip.w < 0.5)
    u = clamp(u, 0.0, 1.0);
  float cycles = float(loop.shape.w);
  float phase = u - loop.origin.w;
  phase -= cycles * floor(phase / cycles);
  float f = phase * loop.spacing.w;
  float whole = floor(f);
  int f0 = int(whole) % loop.shape.z;
  int f1 = (f0 + 1) % loop.shape.z;
  uvec2 a = clothPositions[loop.shape.x + f0 * loop.shape.y + v.y];
  uvec2 b = clothPositions[loop.shape.x + f1 * loop.shape.y + v.y];
  vec3 qa =
      loop.origin.xyz + vec3(float(a.x & 0xffffu), float(a.x >> 16), float(a.y)) * loop.spacing.xyz;
  vec3 qb =
      loop.origin.xyz + vec3(float(b.x & 0xffffu), float(b.x >> 16), float(b.y)) * loop.spacing.xyz;
  bindPosition = (u_rootBind * vec4(mix(qa, qb, f - whole), 1.0)).xyz;
  return true;
}

// A joint at one clip time: from the instance's palette where there is one (>= 0), which holds
// a crossfade's blend already, else from the texture's frames.
mat3x4 jointAt(int palette, ClipTime t, int joint) {
  return palette >= 0 ? paletteJoint(palette, joint) : jointRows(t.f0, t.f1, t.alpha, joint);
}

// A garment vertex at one clip time: its loop's position on the top joint, or its skinning.
vec3 clothOrSkinned(ClipTime t, float clipIndex, float offset, float speed, ivec2 v, vec4 ids,
                    vec4 weights, int palette) {
  vec3 q;
  if (clothAt(clipIndex, offset, speed, v, q))
    return vec4(q, 1.0) * jointAt(palette, t, u_rootJoint);
  vec3 skinned = vec3(0);
  for (int k = 0; k < 4; ++k)
    if (weights[k] != 0.0)
      skinned += weights[k] * (vec4(a_position, 1.0) * jointAt(palette, t, int(ids[k])));
  return skinned;
}

void main() {
  vec4 rows[3];
  vec4 params, fade;
  if (u_naive) {
    rows = u_rows;
    params = u_params[0];
    fade = u_params[1];
  } else {
    rows = instances[a_instance].rows;
    params = instances[a_instance].params;
    fade = instances[a_instance].fade;
  }
  ClipTime now = clipTime(params.x, params.y, params.z);
  // The new clip's share of a crossfade (ClipState::weightAt); below 1 the old clip blends in.
  float weight = fade.x < 0.0 || fade.w <= 0.0 ? 1.0 : clamp((u_time - fade.z) / fade.w, 0.0, 1.0);
  ClipTime before = clipTime(max(fade.x, 0.0), fade.y, params.z);
  int jointPalette = !u_palettes ? -1 : u_naive ? u_palette : paletteOf[a_instance];

  int texel = gl_VertexID * 2;
  vec4 ids = texelFetch(u_skin, ivec2(texel % u_skinWidth, texel / u_skinWidth), 0);
  vec4 weights = texelFetch(u_skin, ivec2((texel + 1) % u_skinWidth, (texel + 1) / u_skinWidth), 0);
  vec3 bindPosition = a_position, bindNormal = a_normal;
  if (u_morphs && weight < 1.0) {
    addMorphs(before, 1.0 - weight, bindPosition, bindNormal);
    addMorphs(now, weight, bindPosition, bindNormal);
  } else if (u_morphs) {
    addMorphs(now, 1.0, bindPosition, bindNormal);
  }
  vec4 p = vec4(bindPosition, 1.0);
  vec3 skinned = vec3(0), normal = vec3(0);
  ivec2 cloth = u_cloth ? clothVertices[gl_VertexID] : ivec2(-1);
  // A zero normal marks a flat-shaded vertex (the LOD bake's weld): shaded by its face too.
  v_facet = cloth.x >= 0 || dot(a_normal, a_normal) == 0.0 ? 1.0 : 0.0;
  if (cloth.x >= 0) { // a garment that may have a loop over the clip: mixed by position in a fade
    skinned = clothOrSkinned(now, params.x, params.y, params.z, cloth, ids, weights, jointPalette);
    if (weight < 1.0)
      skinned = mix(clothOrSkinned(before, max(fade.x, 0.0), fade.y, params.z, cloth, ids, weights,
                                   jointPalette),
                    skinned, weight);
  } else
    for (int k = 0; k < 4; ++k) {
      if (weights[k] == 0.0)
        continue;
      mat3x4 m = jointPalette >= 0 || weight >= 1.0
                     ? jointAt(jointPalette, now, int(ids[k]))
                     : rowsOf(mixRigid(jointRigid(before.f0, before.f1, before.alpha, int(ids[k])),
                                       jointRigid(now.f0, now.f1, now.alpha, int(ids[k])), weight));
      skinned += weights[k] * (p * m);
      normal += weights[k] * (vec4(bindNormal, 0.0) * m);
    }
  vec3 world = vec3(dot(rows[0], vec4(skinned, 1)), dot(rows[1], vec4(skinned, 1)),
                    dot(rows[2], vec4(skinned, 1)));
  v_normal = vec3(dot(rows[0].xyz, normal), dot(rows[1].xyz, normal), dot(rows[2].xyz, normal));
  if (u_shadow.w > 0.5)
    world -= u_shadow.xyz * ((world.y - rows[1].w - 0.02) / max(u_shadow.y, 0.05));
  v_world = world;
  v_uv = a_uv;
  v_colour = colours[int(params.w) * u_subMeshCount + u_subMesh];
  gl_Position = u_viewProjection * vec4(world, 1.0);
}
