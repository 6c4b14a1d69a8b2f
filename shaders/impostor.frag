#version 450 core
// Per-pixel lighting of an impostor from its normal map, the colour of each texel's region from
// the instance's palette, re-textured through the UV map. Texels are fetched, never filtered:
// region ids must not be averaged (the mip levels were built with a mode filter). Normals and UVs
// are BC5 blocks the GPU decodes; the normal is octahedral.
in vec2 v_texel;
flat in vec4 v_rect;
flat in int v_layer, v_level, v_flip;
flat in vec3 v_rows0, v_rows1, v_rows2;
flat in float v_palette;

layout(binding = 0) uniform sampler2DArray u_normals;  // octahedral normal
layout(binding = 1) uniform sampler2DArray u_uvs;      // u, v
layout(binding = 3) uniform usampler2DArray u_regions; // region id + 1
layout(binding = 2) uniform sampler2D u_diffuse;
layout(std430, binding = 2) readonly buffer Palettes { vec4 colours[]; };
uniform bool u_hasTexture, u_hasUvs;
uniform int u_subMeshCount;
uniform vec3 u_lightDirection;
uniform vec4 u_shadow;                                  // crowd.frag's
layout(binding = 5) uniform sampler2D u_shadowHeights; // crowd.frag's
uniform vec4 u_grid;
in vec3 v_world;
out vec4 o_colour;

float inLight(vec3 world) {
  if (u_grid.w < 0.5) return 1.0;
  ivec2 cell = ivec2(floor((world.xz - u_grid.xy) * u_grid.z));
  if (any(lessThan(cell, ivec2(0))) || any(greaterThanEqual(cell, textureSize(u_shadowHeights, 0))))
    return 1.0;
  return world.y >= texelFetch(u_shadowHeights, cell, 0).r ? 1.0 : 0.0;
}

void main() {
  vec2 t = clamp(v_texel, vec2(0), v_rect.zw - 0.001);
  if (v_flip == 1) t.x = v_rect.z - 0.001 - t.x;
  ivec3 at = ivec3((ivec2(v_rect.xy) + ivec2(t)) >> v_level, v_layer);
  int region = int(texelFetch(u_regions, at, v_level).r);
  // Sampled before the discard: implicit derivatives need the whole 2x2 pixel quad.
  vec3 textured = u_hasTexture && u_hasUvs ? texture(u_diffuse, texelFetch(u_uvs, at, v_level).xy).rgb
                                           : vec3(1.0);
  if (region == 0) discard;
  if (u_shadow.w > 0.5) { o_colour = vec4(vec3(0.55), 1.0); return; }
  vec2 o = texelFetch(u_normals, at, v_level).rg * 2.0 - 1.0;
  vec3 n = vec3(o, 1.0 - abs(o.x) - abs(o.y));
  if (n.z < 0.0) n.xy = (1.0 - abs(n.yx)) * vec2(n.x < 0.0 ? -1.0 : 1.0, n.y < 0.0 ? -1.0 : 1.0);
  if (v_flip == 1) n.x = -n.x;
  n = normalize(vec3(dot(v_rows0, n), dot(v_rows1, n), dot(v_rows2, n)));
  float diffuse = max(dot(n, u_lightDirection), 0.0) * inLight(v_world);
  // As on the geometry: A of the region's colour says how much the texture applies (garments of a
  // clothed pack are not textured).
  vec4 colour = colours[int(v_palette) * u_subMeshCount + min(region, u_subMeshCount) - 1];
  vec3 albedo = colour.rgb * mix(vec3(1.0), textured, colour.a);
  o_colour = vec4(albedo * (0.25 + 0.75 * diffuse), 1.0);
}
