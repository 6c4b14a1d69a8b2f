#version 450 core
// Skinned instancing: joint transforms come from the animation texture (two frames, blended
// exactly as runtime/src/texture_skinning.cpp does on the CPU), ids and weights from the
// skin-weight texture, per-instance data from one buffer indexed by the instance's id (an instanced attribute).

layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;
layout(location = 2) in vec2 a_uv;
layout(location = 3) in uint a_instance; // per instance: which one (culled and sorted by level)

layout(binding = 0) uniform sampler2D u_animation; // RGBA32F or RGBA16F texels
layout(binding = 1) uniform sampler2D u_skin;      // RGBA32F: ids, weights

struct Instance {
  vec4 rows[3]; // world transform, 3x4
  vec4 params;  // clip, time offset (s), speed, palette
};
layout(std430, binding = 0) readonly buffer Clips { vec4 clips[]; }; // fps, frames, first, loop
layout(std430, binding = 1) readonly buffer Instances { Instance instances[]; };
layout(std430, binding = 2) readonly buffer Palettes { vec4 colours[]; };

uniform mat4 u_viewProjection;
uniform float u_time;
uniform int u_encoding; // 0: matrix 3x4 (3 texels), 1: quaternion + translation/scale (2)
uniform int u_jointCount;
uniform int u_framesPerRow;
uniform int u_skinWidth;
uniform int u_subMesh;
uniform int u_subMeshCount;
// Naive path: one draw per instance, its data in uniforms instead of the buffer.
uniform bool u_naive;
uniform vec4 u_rows[3];
uniform vec4 u_params;

out vec3 v_normal;
out vec4 v_colour; // A: how much the diffuse texture applies
out vec2 v_uv;

ivec2 texelOf(int frame, int joint, int texel) {
  int tpj = u_encoding == 0 ? 3 : 2;
  return ivec2((frame % u_framesPerRow) * u_jointCount * tpj + joint * tpj + texel,
               frame / u_framesPerRow);
}

mat3x4 rowsFromQts(vec4 q, vec4 ts) {
  float x = q.x, y = q.y, z = q.z, w = q.w, s = ts.w;
  return mat3x4(vec4(s * (1 - 2 * (y * y + z * z)), s * 2 * (x * y - w * z), s * 2 * (x * z + w * y), ts.x),
                vec4(s * 2 * (x * y + w * z), s * (1 - 2 * (x * x + z * z)), s * 2 * (y * z - w * x), ts.y),
                vec4(s * 2 * (x * z - w * y), s * 2 * (y * z + w * x), s * (1 - 2 * (x * x + y * y)), ts.z));
}

// Hamilton product of quaternions stored (x, y, z, w).
vec4 qmul(vec4 a, vec4 b) {
  return vec4(a.w * b.xyz + b.w * a.xyz + cross(a.xyz, b.xyz), a.w * b.w - dot(a.xyz, b.xyz));
}

mat3x4 jointRows(int f0, int f1, float alpha, int joint) {
  if (u_encoding == 0) {
    return mat3x4(mix(texelFetch(u_animation, texelOf(f0, joint, 0), 0), texelFetch(u_animation, texelOf(f1, joint, 0), 0), alpha),
                  mix(texelFetch(u_animation, texelOf(f0, joint, 1), 0), texelFetch(u_animation, texelOf(f1, joint, 1), 0), alpha),
                  mix(texelFetch(u_animation, texelOf(f0, joint, 2), 0), texelFetch(u_animation, texelOf(f1, joint, 2), 0), alpha));
  }
  // Dual-quaternion (screw-linear) blend of rotation and translation; scale blends linearly.
  vec4 q0 = texelFetch(u_animation, texelOf(f0, joint, 0), 0);
  vec4 q1 = texelFetch(u_animation, texelOf(f1, joint, 0), 0);
  vec4 ts0 = texelFetch(u_animation, texelOf(f0, joint, 1), 0);
  vec4 ts1 = texelFetch(u_animation, texelOf(f1, joint, 1), 0);
  if (dot(q0, q1) < 0) q1 = -q1;
  vec4 real = mix(q0, q1, alpha);
  vec4 dual = mix(0.5 * qmul(vec4(ts0.xyz, 0), q0), 0.5 * qmul(vec4(ts1.xyz, 0), q1), alpha);
  float len = length(real);
  real /= len;
  dual /= len;
  vec3 translation = 2.0 * qmul(dual, vec4(-real.xyz, real.w)).xyz;
  return rowsFromQts(real, vec4(translation, mix(ts0.w, ts1.w, alpha)));
}

void main() {
  vec4 rows[3];
  vec4 params;
  if (u_naive) {
    rows = u_rows;
    params = u_params;
  } else {
    rows = instances[a_instance].rows;
    params = instances[a_instance].params;
  }
  vec4 clip = clips[int(params.x)];
  float last = clip.y - 1.0;
  float f = (u_time * params.z + params.y) * clip.x;
  if (clip.w > 0.5 && last > 0) f = f - last * floor(f / last);
  f = clamp(f, 0.0, last);
  int frame = int(floor(f));
  float alpha = f - float(frame);
  int f0 = int(clip.z) + min(frame, int(last));
  int f1 = int(clip.z) + min(frame + 1, int(last));

  int texel = gl_VertexID * 2;
  vec4 ids = texelFetch(u_skin, ivec2(texel % u_skinWidth, texel / u_skinWidth), 0);
  vec4 weights = texelFetch(u_skin, ivec2((texel + 1) % u_skinWidth, (texel + 1) / u_skinWidth), 0);
  vec4 p = vec4(a_position, 1.0);
  vec3 skinned = vec3(0), normal = vec3(0);
  for (int k = 0; k < 4; ++k) {
    if (weights[k] == 0.0) continue;
    mat3x4 m = jointRows(f0, f1, alpha, int(ids[k]));
    skinned += weights[k] * (p * m);
    normal += weights[k] * (vec4(a_normal, 0.0) * m);
  }
  vec3 world = vec3(dot(rows[0], vec4(skinned, 1)), dot(rows[1], vec4(skinned, 1)), dot(rows[2], vec4(skinned, 1)));
  v_normal = vec3(dot(rows[0].xyz, normal), dot(rows[1].xyz, normal), dot(rows[2].xyz, normal));
  v_uv = a_uv;
  v_colour = colours[int(params.w) * u_subMeshCount + u_subMesh];
  gl_Position = u_viewProjection * vec4(world, 1.0);
}
