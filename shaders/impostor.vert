#version 450 core
// Impostors: one quad per instance, facing the camera, covering the three stored views that
// impostor.frag blends (runtime/src/impostor_runtime.cpp chooses the same views and weights on
// the CPU; the bake's accuracy check measures that blend).

struct Instance {
  vec4 rows[3]; // world transform, 3x4 (rotation about +Y, translation)
  vec4 params;  // clip, time offset (s), speed, palette
  vec4 fade;    // crowd.vert's; an instance in a fade never draws as an impostor
};
layout(std430, binding = 0) readonly buffer Clips { vec4 clips[]; }; // fps, frames, first, loop
layout(std430, binding = 1) readonly buffer Instances { Instance instances[]; };
layout(std430, binding = 3) readonly buffer Drawn { uint drawn[]; };
// Three vec4 per stored view (pack::ImpostorView): crop rectangle (x, y, w, h) in the atlas; pivot
// x, y (the sphere centre, texels from the crop's corner), plane offset, 0; plane slopes x, y, 0, 0.
layout(std430, binding = 4) readonly buffer Views { vec4 views[]; };
// impostor.frag's: per (level, view) at level * u_viewCount + view, x is the view's first row.
layout(std430, binding = 7) readonly buffer Spans { uvec2 spans[]; };
uniform int u_viewCount;
uniform mat4 u_viewProjection;
uniform float u_time;
uniform vec3 u_eye;
uniform vec4 u_sphere;         // centre, radius (model units)
uniform ivec4 u_layout;        // azimuths, elevations, stored azimuths, frames
uniform float u_texelSize;     // model units per texel: 2 radius / texels
uniform float u_diffusePerTexel; // diffuse texels per texel (runtime::diffuseTexelsPerUnit)
uniform bool u_mirrored;
uniform float u_frameStep;     // seconds between frames
uniform float u_oneToOne;      // distance where a texel covers a pixel
uniform int u_maxLevel;
// impostor.frag's region ids: where frame f's level l starts, f * u_regionFrameWords +
// u_regionLevelWord[l], and its rows' words.
uniform int u_regionFrameWords;
uniform int u_regionLevelWord[6], u_regionRowWords[6]; // runtime::kImpostorMaxMipLevels
// A world's shadow pass (crowd.vert's): the view from the light, flat on the ground.
uniform vec4 u_shadow;

// Per blended view, where the ray through this point of the quad meets the view's plane, in
// texels of the atlas at this mip level less half a texel (texel centres at whole numbers),
// homogeneous (x w, y w, w): interpolated across the quad and divided per pixel, exact. Everything
// the fragment shader needs that is the same for the whole instance is worked out here, once.
out vec3 v_crop[3];
flat out ivec4 v_bounds[3];    // the views' crops at this level: first texel x, y, last x, y
flat out ivec3 v_regionRow;    // the views' frames' region words at this level, row 0
flat out int v_regionRowWords; // words per row at this level
flat out ivec3 v_layer;        // the views' atlas layers * 2 + flip
flat out ivec3 v_rows;         // the views' first rows in Spans at this level
flat out vec3 v_weight;        // the views' weights, heaviest first (0: unused)
flat out int v_level;
flat out int v_diffuseLevel;   // the diffuse texture's mip level (impostor.frag clamps it)
flat out vec3 v_rows0, v_rows1, v_rows2;
flat out float v_palette;
out vec3 v_world;

const float PI = 3.14159265358979;

// The sampled direction (azimuth a, elevation row e): from the centre towards its camera, and
// the image's right and up (runtime::impostorViewFrame).
void viewFrame(int a, int e, out vec3 dir, out vec3 right, out vec3 up) {
  float az = 2.0 * PI * float(a) / float(u_layout.x);
  float el = 0.5 * PI * (float(e) + 0.5) / float(u_layout.y);
  dir = vec3(cos(el) * sin(az), sin(el), cos(el) * cos(az));
  right = normalize(cross(-dir, vec3(0, 1, 0)));
  up = cross(right, -dir);
}

// The stored view's plane in the character's frame, dot(p - centre, n) = offset, returned as
// (n, offset); drawn flipped, its x slope turns round.
vec4 viewPlane(int view, bool flip, vec3 dir, vec3 right, vec3 up) {
  vec4 slopes = views[3 * view + 2];
  return vec4(dir - (flip ? -slopes.x : slopes.x) * right - slopes.y * up, views[3 * view + 1].z);
}

void main() {
  uint id = drawn[gl_InstanceID];
  vec4 rows[3] = instances[id].rows;
  vec4 params = instances[id].params;
  mat3 toLocal = mat3(rows[0].xyz, rows[1].xyz, rows[2].xyz); // the inverse rotation
  vec3 origin = vec3(rows[0].w, rows[1].w, rows[2].w);
  bool shadow = u_shadow.w > 0.5;
  // The camera in the character's frame, from the sphere centre (a shadow: towards the light).
  vec3 eye = toLocal * (u_eye - origin) - u_sphere.xyz;
  vec3 toEye = shadow ? toLocal * u_shadow.xyz : eye;

  // Texels per pixel grow with distance past the 1:1 distance: fetch the matching mip level.
  vec3 centre = transpose(toLocal) * u_sphere.xyz + origin;
  float texelsPerPixel = length(u_eye - centre) / u_oneToOne;
  v_level = clamp(int(floor(log2(max(texelsPerPixel, 1.0)))), 0, u_maxLevel);
  // The diffuse texture's level for the whole impostor, from its texels per pixel (an impostor is
  // far: one level for all its pixels is what the geometry's derivatives would give, near enough),
  // the nearest whole level.
  v_diffuseLevel = int(round(log2(max(texelsPerPixel * u_diffusePerTexel, 1e-6))));

  int A = u_layout.x, E = u_layout.y, stored = u_layout.z, F = u_layout.w;
  vec4 clip = clips[int(params.x)];
  float f = (u_time * params.z + params.y) / u_frameStep;
  if (clip.w > 0.5) f -= float(F) * floor(f / float(F));
  int frame = int(round(clamp(f, 0.0, clip.w > 0.5 ? float(F) : float(F - 1)))) % F;

  // The three sampled directions around the camera's on the (azimuth, elevation) grid, each cell
  // split in two triangles, with barycentric weights (runtime::chooseImpostorViews).
  float ga = atan(toEye.x, toEye.z) / (2.0 * PI / float(A));
  float el = asin(clamp(toEye.y / max(length(toEye), 1e-20), 0.0, 1.0));
  float ge = clamp(el / (0.5 * PI / float(E)) - 0.5, 0.0, float(E - 1));
  int a0 = int(floor(ga)), e0 = min(int(ge), E - 1), e1 = min(e0 + 1, E - 1);
  float s = ga - float(a0), t = ge - float(e0);
  ivec2 corners[3];
  vec3 weights;
  if (s + t <= 1.0) {
    corners = ivec2[3](ivec2(a0, e0), ivec2(a0 + 1, e0), ivec2(a0, e1));
    weights = vec3(1.0 - s - t, s, t);
  } else {
    corners = ivec2[3](ivec2(a0 + 1, e1), ivec2(a0 + 1, e0), ivec2(a0, e1));
    weights = vec3(s + t - 1.0, 1.0 - t, 1.0 - s);
  }
  // Heaviest first, ties in corner order (the CPU's stable sort).
  for (int i = 0; i < 2; ++i)
    for (int j = 0; j < 2 - i; ++j)
      if (weights[j + 1] > weights[j]) {
        float w = weights[j]; weights[j] = weights[j + 1]; weights[j + 1] = w;
        ivec2 c = corners[j]; corners[j] = corners[j + 1]; corners[j + 1] = c;
      }

  // The quad: on the plane through the centre facing the camera, bounding each view's crop
  // (on that view's plane) as seen from the camera, a texel of margin for the bilinear edge.
  // Points are relative to the sphere centre, in the character's frame.
  vec3 facing = normalize(toEye);
  vec3 qRight = abs(facing.y) < 0.999 ? normalize(cross(vec3(0, 1, 0), facing)) : vec3(1, 0, 0);
  vec3 qUp = cross(facing, qRight);
  vec2 low = vec2(1e30), high = vec2(-1e30);
  vec3 rights[3], ups[3];
  vec4 planes[3];
  vec2 pivots[3], rects[3];
  for (int k = 0; k < 3; ++k) {
    int a = ((corners[k].x % A) + A) % A, e = corners[k].y, layer = frame, sa = a;
    bool flip = u_mirrored && a > A / 2;
    if (flip) {
      layer = (frame + F / 2) % F;
      sa = A - a;
    }
    int view = (layer * E + e) * stored + sa;
    vec3 dir;
    viewFrame(a, e, dir, rights[k], ups[k]);
    vec4 rect = views[3 * view];
    planes[k] = viewPlane(view, flip, dir, rights[k], ups[k]);
    pivots[k] = views[3 * view + 1].xy;
    rects[k] = rect.xy;
    ivec4 r = ivec4(rect);
    v_bounds[k] = ivec4(r.xy, r.xy + r.zw - 1) >> v_level;
    v_regionRow[k] = layer * u_regionFrameWords + u_regionLevelWord[v_level];
    v_layer[k] = layer * 2 + (flip ? 1 : 0);
    v_rows[k] = int(spans[v_level * u_viewCount + view].x);
    if (flip) rights[k] = -rights[k]; // crop x runs the other way
    if (weights[k] <= 0.0)
      continue;
    for (int c = 0; c < 4; ++c) {
      // The crop's corner: model units along the view's right and up, then onto its plane.
      vec2 at = (vec2(c & 1, c >> 1) * rect.zw - pivots[k]) * vec2(1, -1) * u_texelSize;
      vec3 p = rights[k] * at.x + ups[k] * at.y;
      p += dir * (planes[k].w - dot(p, planes[k].xyz)) / dot(dir, planes[k].xyz);
      // Along the ray to the camera (or the light) onto the quad's plane.
      vec3 ray = shadow ? -facing : p - eye;
      float along = dot(ray, facing);
      vec3 q = p - ray * (dot(p, facing) / (abs(along) > 1e-6 ? along : -1e-6));
      low = min(low, vec2(dot(q, qRight), dot(q, qUp)));
      high = max(high, vec2(dot(q, qRight), dot(q, qUp)));
    }
  }
  v_weight = weights;
  v_regionRowWords = u_regionRowWords[v_level];
  low -= u_texelSize, high += u_texelSize;
  vec2 c = vec2(gl_VertexID & 1, gl_VertexID >> 1); // a strip of 4 corners
  vec3 local = u_sphere.xyz + qRight * mix(low.x, high.x, c.x) + qUp * mix(high.y, low.y, c.y);
  // Where the ray through this corner meets each view's plane, in crop texels, homogeneous: for a
  // camera, the point on plane k times d = dot(ray, n), affine in the corner, over d.
  vec3 x = local - u_sphere.xyz;
  for (int k = 0; k < 3; ++k) {
    vec3 n = planes[k].xyz;
    vec3 ray = shadow ? -facing : x - eye, from = shadow ? x : eye;
    float d = dot(ray, n);
    vec3 q = from * d + ray * (planes[k].w - dot(from, n)); // the point times d
    if (shadow) q /= d, d = 1.0;
    vec2 crop = vec2(pivots[k].x * d + dot(q, rights[k]) / u_texelSize,
                     pivots[k].y * d - dot(q, ups[k]) / u_texelSize);
    float scale = 1.0 / float(1 << v_level);
    v_crop[k] = vec3((crop + (rects[k] - 0.5 / scale) * d) * scale, d);
  }
  vec3 world = vec3(dot(rows[0], vec4(local, 1)), dot(rows[1], vec4(local, 1)),
                    dot(rows[2], vec4(local, 1)));
  if (shadow)
    world -= u_shadow.xyz * ((world.y - rows[1].w - 0.02) / max(u_shadow.y, 0.05));
  v_world = world;
  gl_Position = u_viewProjection * vec4(world, 1.0);

  v_rows0 = rows[0].xyz;
  v_rows1 = rows[1].xyz;
  v_rows2 = rows[2].xyz;
  v_palette = params.w;
}
