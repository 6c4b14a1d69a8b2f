#version 450 core
// Per-pixel lighting of an impostor from its normal map, the colour of each texel's region from
// the instance's palette, re-textured through the UV map. impostor.vert gives, per blended view,
// where the pixel's ray meets the view's plane in crop texels; there a view covers by its four
// nearest texels' coverage, bilinearly, and the pixel is drawn where the weighted coverage reaches
// half. The normal is the weighted mean of the views whose nearest texel is covered, the region
// and UV the heaviest such view's: region ids are never averaged (the mip levels were built with
// a mode filter), and texels are fetched, not filtered. Normals and UVs are BC5 blocks the GPU
// decodes, kept only in each view's spans (formats/impostor_spans.h): a covered texel's are read
// through its row's span. The normal is octahedral. runtime::sampleImpostor does the same on the
// CPU. The diffuse texture is read at impostor.vert's level, the same for every pixel.
in vec3 v_crop[3];
flat in ivec4 v_bounds[3];
flat in ivec3 v_regionRow;
flat in int v_regionRowWords;
flat in ivec3 v_layer;
flat in ivec3 v_rows;
flat in vec3 v_weight;
flat in int v_level;
flat in int v_diffuseLevel;
flat in vec3 v_rows0, v_rows1, v_rows2;
flat in float v_palette;

layout(binding = 0) uniform sampler2DArray u_normals;  // octahedral normal, pool of blocks
layout(binding = 1) uniform sampler2DArray u_uvs;      // u, v, the same pool
// Region id + 1 (0: empty), 4 or 8 bits a texel in 32-bit words, the lower bits the left texel,
// rows of whole words, each frame's mip levels one after another (impostor.vert gives where a
// view's level starts; a storage buffer: no texture layout of the mip levels is needed).
layout(std430, binding = 5) readonly buffer Regions { uint regionWords[]; };
uniform int u_regionBits;
// Rows of spans (impostor.vert gives each view's first at this level): x, the pool block of the
// row's first stored block; y, its block column.
layout(std430, binding = 7) readonly buffer Spans { uvec2 spans[]; };
uniform int u_poolShift; // a pool row holds 1 << u_poolShift blocks
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

// The ids of texels `a` and `b` of a row (x: a's column, y: b's; z: the row) at this level.
uvec2 regionPair(ivec3 at, int level0) {
  int row = level0 + at.z * v_regionRowWords;
  int bitA = at.x * u_regionBits, bitB = at.y * u_regionBits;
  uvec2 words = uvec2(regionWords[row + (bitA >> 5)], regionWords[row + (bitB >> 5)]);
  return (words >> uvec2(bitA & 31, bitB & 31)) & ((1u << u_regionBits) - 1u);
}

vec3 octahedral(vec2 o) {
  o = o * 2.0 - 1.0;
  vec3 n = vec3(o, 1.0 - abs(o.x) - abs(o.y));
  if (n.z < 0.0) n.xy = (1.0 - abs(n.yx)) * vec2(n.x < 0.0 ? -1.0 : 1.0, n.y < 0.0 ? -1.0 : 1.0);
  return normalize(n);
}

// One blended view's coverage of the pixel (from the four nearest texels of this level, inside
// the crop, bilinearly), its nearest texel and that texel's region (0: uncovered).
float viewCover(vec3 crop, ivec4 bounds, int regionRow, out ivec2 nearest, out int region) {
  ivec2 first = bounds.xy, last = bounds.zw;
  vec2 p = crop.xy / crop.z;
  ivec2 base = ivec2(floor(p));
  vec2 f = p - vec2(base);
  // Which of the two columns and two rows lie inside the crop (past it: another view's texels).
  bvec2 in0 = equal(clamp(base, first, last), base);
  bvec2 in1 = equal(clamp(base + 1, first, last), base + 1);
  bvec2 nearHigh = greaterThanEqual(f, vec2(0.5));
  // Read inside the crop only (clamped), then masked.
  ivec2 c0 = clamp(base, first, last), c1 = clamp(base + 1, first, last);
  uvec2 row0 = regionPair(ivec3(c0.x, c1.x, c0.y), regionRow);
  uvec2 row1 = regionPair(ivec3(c0.x, c1.x, c1.y), regionRow);
  int r00 = in0.x && in0.y ? int(row0.x) : 0;
  int r10 = in1.x && in0.y ? int(row0.y) : 0;
  int r01 = in0.x && in1.y ? int(row1.x) : 0;
  int r11 = in1.x && in1.y ? int(row1.y) : 0;
  region = nearHigh.y ? (nearHigh.x ? r11 : r01) : (nearHigh.x ? r10 : r00);
  nearest = base + ivec2(nearHigh);
  return mix(mix(float(r00 != 0), float(r10 != 0), f.x), mix(float(r01 != 0), float(r11 != 0), f.x),
             f.y);
}

void main() {
  // First the coverage and each view's nearest region, then the discard: the GPU (and llvmpipe,
  // per block of pixels) skips the fetches below where no pixel of the group is covered.
  ivec2 near[3];
  ivec3 rz = ivec3(0);
  float cover = v_weight[0] * viewCover(v_crop[0], v_bounds[0], v_regionRow[0], near[0], rz[0]);
  if (v_weight[1] > 0.0)
    cover += v_weight[1] * viewCover(v_crop[1], v_bounds[1], v_regionRow[1], near[1], rz[1]);
  if (v_weight[2] > 0.0)
    cover += v_weight[2] * viewCover(v_crop[2], v_bounds[2], v_regionRow[2], near[2], rz[2]);
  if (cover < 0.5 || rz == ivec3(0)) discard;
  // The nearest texel of each view that covers it: its normal, region and UV, in its row's span.
  vec3 normal = vec3(0.0);
  int region = 0;
  ivec3 chosen = ivec3(0);
  for (int k = 0; k < 3; ++k) {
    if (rz[k] == 0) continue;
    ivec2 nearest = near[k];
    int layer = v_layer[k] >> 1;
    uvec2 span = spans[v_rows[k] + (nearest.y >> 2) - (v_bounds[k].y >> 2)];
    uint block = span.x + uint(nearest.x >> 2) - span.y;
    ivec2 pool = ivec2(block & ((1u << u_poolShift) - 1u), block >> u_poolShift);
    ivec3 at = ivec3(pool * 4 + (nearest & 3), layer);
    vec3 n = octahedral(texelFetch(u_normals, at, 0).rg);
    if ((v_layer[k] & 1) == 1) n.x = -n.x;
    normal += v_weight[k] * n;
    if (region == 0) region = rz[k], chosen = at;
  }
  if (u_shadow.w > 0.5) { o_colour = vec4(vec3(0.55), 1.0); return; }
  vec2 uv = texelFetch(u_uvs, chosen, 0).xy;
  // The diffuse texel nearest the UV at the nearest mip level, fetched: the impostor's own texels
  // are fetched too, and llvmpipe filters a level given per pixel (textureLod) 7x slower.
  vec3 textured = vec3(1.0);
  if (u_hasTexture && u_hasUvs) {
    int level = clamp(v_diffuseLevel, 0, textureQueryLevels(u_diffuse) - 1);
    ivec2 size = textureSize(u_diffuse, level);
    textured = texelFetch(u_diffuse, min(ivec2(uv * vec2(size)), size - 1), level).rgb;
  }
  vec3 n = normalize(normal);
  n = normalize(vec3(dot(v_rows0, n), dot(v_rows1, n), dot(v_rows2, n)));
  float diffuse = max(dot(n, u_lightDirection), 0.0) * inLight(v_world);
  // As on the geometry: A of the region's colour says how much the texture applies (garments of a
  // clothed pack are not textured).
  vec4 colour = colours[int(v_palette) * u_subMeshCount + min(region, u_subMeshCount) - 1];
  vec3 albedo = colour.rgb * mix(vec3(1.0), textured, colour.a);
  o_colour = vec4(albedo * (0.25 + 0.75 * diffuse), 1.0);
}
