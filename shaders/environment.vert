#version 450 core
// The environment's mesh (a crowdbake terrain pack), in world space with its vertex colours.
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;
layout(location = 2) in vec4 a_colour;
uniform mat4 u_viewProjection;
out vec3 v_world;
out vec3 v_normal;
out vec4 v_colour;

void main() {
  v_world = a_position;
  v_normal = a_normal;
  v_colour = a_colour;
  gl_Position = u_viewProjection * vec4(a_position, 1.0);
}
