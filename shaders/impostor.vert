#version 450 core
// Impostors: one quad per instance, on the best impostor plane of the stored view nearest to
// the camera direction (runtime/src/impostor_runtime.cpp chooses the same view on the CPU).

struct Instance {
  vec4 rows[3]; // world transform, 3x4 (rotation about +Y, translation)
  vec4 params;  // clip, time offset (s), speed, palette
  vec4 fade;    // crowd.vert's; an instance in a fade never draws as an impostor
};
layout(std430, binding = 0) readonly buffer Clips { vec4 clips[]; }; // fps, frames, first, loop
layout(std430, binding = 1) readonly buffer Instances { Instance instances[]; };
layout(std430, binding = 3) readonly buffer Drawn { uint drawn[]; };
// Two vec4 per stored view: crop rectangle (x, y, w, h); pivot x, y, plane offset, 0.
layout(std430, binding = 4) readonly buffer Views { vec4 views[]; };

uniform mat4 u_viewProjection;
uniform float u_time;
uniform vec3 u_eye;
uniform vec4 u_sphere;         // centre, radius (model units)
uniform ivec4 u_layout;        // azimuths, elevations, stored azimuths, frames
uniform bool u_mirrored;
uniform float u_frameStep;     // seconds between frames
uniform float u_texelSize;     // model units per texel: 2 radius / texels
uniform float u_oneToOne;      // distance where a texel covers a pixel
uniform int u_maxLevel;
// A world's shadow pass (crowd.vert's): the view from the light, flat on the ground.
uniform vec4 u_shadow;

out vec2 v_texel;              // texels from the crop's corner, as drawn (before flipping)
flat out vec4 v_rect;
flat out int v_layer, v_level, v_flip;
flat out vec3 v_rows0, v_rows1, v_rows2;
flat out float v_palette;
out vec3 v_world;

const float PI = 3.14159265358979;

void main() {
  uint id = drawn[gl_InstanceID];
  vec4 rows[3] = instances[id].rows;
  vec4 params = instances[id].params;
  mat3 toLocal = mat3(rows[0].xyz, rows[1].xyz, rows[2].xyz); // the inverse rotation
  vec3 centre = transpose(toLocal) * u_sphere.xyz + vec3(rows[0].w, rows[1].w, rows[2].w);
  vec3 toEye = toLocal * (u_shadow.w > 0.5 ? u_shadow.xyz : u_eye - centre);

  int A = u_layout.x, E = u_layout.y, stored = u_layout.z, F = u_layout.w;
  vec4 clip = clips[int(params.x)];
  float f = (u_time * params.z + params.y) / u_frameStep;
  if (clip.w > 0.5) f -= float(F) * floor(f / float(F));
  int frame = int(round(clamp(f, 0.0, clip.w > 0.5 ? float(F) : float(F - 1)))) % F;
  int a = int(round(atan(toEye.x, toEye.z) / (2.0 * PI / float(A))));
  a = ((a % A) + A) % A;
  float el = asin(clamp(toEye.y / max(length(toEye), 1e-20), 0.0, 1.0));
  int e = min(int(floor(el / (0.5 * PI / float(E)))), E - 1);
  int sa = a, flip = 0;
  if (u_mirrored && a > A / 2) {
    frame = (frame + F / 2) % F;
    sa = A - a;
    flip = 1;
  }
  int view = (frame * E + e) * stored + sa;
  vec4 rect = views[2 * view], pivot = views[2 * view + 1];

  float az = 2.0 * PI * float(a) / float(A), elev = 0.5 * PI * (float(e) + 0.5) / float(E);
  vec3 dir = vec3(cos(elev) * sin(az), sin(elev), cos(elev) * cos(az));
  vec3 right = normalize(cross(-dir, vec3(0, 1, 0)));
  vec3 up = cross(right, -dir);
  // A mirrored view is drawn flipped: its pivot sits as far from the right edge as it was
  // from the left.
  float px = flip == 1 ? rect.z - pivot.x : pivot.x;
  int corner = gl_VertexID % 6;
  vec2 c = vec2(corner == 1 || corner == 2 || corner == 4 ? 1.0 : 0.0,
                corner == 2 || corner == 4 || corner == 5 ? 1.0 : 0.0);
  vec2 texel = c * rect.zw;
  vec3 local = u_sphere.xyz + dir * pivot.z + right * ((texel.x - px) * u_texelSize) +
               up * ((pivot.y - texel.y) * u_texelSize);
  vec3 world = vec3(dot(rows[0], vec4(local, 1)), dot(rows[1], vec4(local, 1)),
                    dot(rows[2], vec4(local, 1)));
  if (u_shadow.w > 0.5)
    world -= u_shadow.xyz * ((world.y - rows[1].w - 0.02) / max(u_shadow.y, 0.05));
  v_world = world;
  gl_Position = u_viewProjection * vec4(world, 1.0);

  v_texel = texel;
  v_rect = rect;
  v_layer = frame;
  v_flip = flip;
  // Texels per pixel grow with distance past the 1:1 distance: fetch the matching mip level.
  v_level = clamp(int(floor(log2(max(length(u_eye - centre) / u_oneToOne, 1.0)))), 0, u_maxLevel);
  v_rows0 = rows[0].xyz;
  v_rows1 = rows[1].xyz;
  v_rows2 = rows[2].xyz;
  v_palette = params.w;
}
