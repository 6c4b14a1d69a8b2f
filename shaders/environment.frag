#version 450 core
// Diffuse lighting of the environment, shaded by the terrain's shadow height map (seed 003,
// §4.5): a point below its cell's shadow height gets no direct light.
in vec3 v_world;
in vec3 v_normal;
in vec4 v_colour;
layout(binding = 0) uniform sampler2D u_shadowHeights; // R32F, one texel a cell
uniform vec4 u_grid;           // origin x, origin z, 1 / cell, unused
uniform vec3 u_lightDirection; // towards the light, normalised
out vec4 o_colour;

void main() {
  vec3 n = normalize(v_normal);
  // A wall stands on the edge of its roof's cells: the shadow height it answers to is that of
  // the cell in front of it, half a cell out along its normal.
  vec2 cell = (v_world.xz + n.xz * (0.6 / u_grid.z) - u_grid.xy) * u_grid.z;
  float shadowHeight = texelFetch(u_shadowHeights, ivec2(floor(cell)), 0).r;
  float lit = v_world.y + 0.05 >= shadowHeight ? 1.0 : 0.0; // 5 cm of slack on flat ground
  float diffuse = max(dot(n, u_lightDirection), 0.0) * lit;
  o_colour = vec4(v_colour.rgb * (0.3 + 0.7 * diffuse), 1.0);
}
