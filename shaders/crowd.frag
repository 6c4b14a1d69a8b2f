#version 450 core
// Per-pixel diffuse lighting of the region colour, modulated by the diffuse texture if any.
// Lit from both sides: a back face's normal is turned towards the viewer.
in vec3 v_normal;
in vec4 v_colour; // A: how much the diffuse texture applies
in vec2 v_uv;
in vec3 v_world;
in float v_facet; // 1: a cloth loop's or flat-shaded vertex: its face's normal (derivatives)
layout(binding = 2) uniform sampler2D u_diffuse;
uniform bool u_hasTexture;
uniform vec3 u_lightDirection; // towards the light, normalised
uniform vec4 u_shadow;         // w = 1: the shadow pass (crowd.vert), a darkening factor out
// A world's shadow height map (seed 003 §4.5): u_grid is origin x, z, 1 / cell and w = 1 with a
// world; a point below its cell's shadow height gets no direct light.
layout(binding = 5) uniform sampler2D u_shadowHeights;
uniform vec4 u_grid;
out vec4 o_colour;

float inLight(vec3 world) {
  if (u_grid.w < 0.5) return 1.0;
  ivec2 cell = ivec2(floor((world.xz - u_grid.xy) * u_grid.z));
  if (any(lessThan(cell, ivec2(0))) || any(greaterThanEqual(cell, textureSize(u_shadowHeights, 0))))
    return 1.0;
  return world.y >= texelFetch(u_shadowHeights, cell, 0).r ? 1.0 : 0.0;
}

void main() {
  if (u_shadow.w > 0.5) { o_colour = vec4(vec3(0.55), 1.0); return; } // multiplies the ground
  vec3 n = normalize(v_normal);
  if (!gl_FrontFacing) n = -n;
  if (v_facet > 0.5) n = normalize(cross(dFdx(v_world), dFdy(v_world))); // faces the viewer
  float diffuse = max(dot(n, u_lightDirection), 0.0) * inLight(v_world);
  vec3 albedo = v_colour.rgb * (u_hasTexture ? mix(vec3(1.0), texture(u_diffuse, v_uv).rgb, v_colour.a) : vec3(1.0));
  o_colour = vec4(albedo * (0.25 + 0.75 * diffuse), 1.0);
}
