#version 450 core
// Per-pixel diffuse lighting of the region colour.
in vec3 v_normal;
in vec3 v_colour;
uniform vec3 u_lightDirection; // towards the light, normalised
out vec4 o_colour;

void main() {
  vec3 n = normalize(v_normal);
  if (!gl_FrontFacing) n = -n;
  float diffuse = max(dot(n, u_lightDirection), 0.0);
  o_colour = vec4(v_colour * (0.25 + 0.75 * diffuse), 1.0);
}
