#version 450 core
// Per-pixel diffuse lighting of the region colour, modulated by the diffuse texture if any.
// Lit from both sides: a back face's normal is turned towards the viewer.
in vec3 v_normal;
in vec4 v_colour; // A: how much the diffuse texture applies
in vec2 v_uv;
in vec3 v_world;
in float v_facet; // 1: a cloth loop's vertex, its normal the face's (screen-space derivatives)
layout(binding = 2) uniform sampler2D u_diffuse;
uniform bool u_hasTexture;
uniform vec3 u_lightDirection; // towards the light, normalised
out vec4 o_colour;

void main() {
  vec3 n = normalize(v_normal);
  if (!gl_FrontFacing) n = -n;
  if (v_facet > 0.5) n = normalize(cross(dFdx(v_world), dFdy(v_world))); // faces the viewer
  float diffuse = max(dot(n, u_lightDirection), 0.0);
  vec3 albedo = v_colour.rgb * (u_hasTexture ? mix(vec3(1.0), texture(u_diffuse, v_uv).rgb, v_colour.a) : vec3(1.0));
  o_colour = vec4(albedo * (0.25 + 0.75 * diffuse), 1.0);
}
